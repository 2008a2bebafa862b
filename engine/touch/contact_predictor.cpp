#include "touch/contact_predictor.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rt {
namespace {

constexpr size_t kMaxSamples = 32;  // a tracker at 120 Hz gives 24 in the history; room to spare

// The smallest tau > 0 with a + b tau + c tau^2 = 0; none where the curve turns before zero.
std::optional<double> first_root_after_now(double a, double b, double c) {
  if (std::abs(c) < 1e-12) {
    if (b >= 0) return std::nullopt;
    return -a / b;
  }
  const double discriminant = b * b - 4 * a * c;
  if (discriminant < 0) return std::nullopt;
  const double root = std::sqrt(discriminant);
  std::optional<double> first;
  for (const double tau : {(-b - root) / (2 * c), (-b + root) / (2 * c)})
    if (tau > 0 && (!first || tau < *first)) first = tau;
  return first;
}

// The mean of the hand's finite joints: a tracker's noise on each joint partly cancels in it.
Eigen::Vector3d hand_centre(const HandSkeleton& hand) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (const Eigen::Vector3d& joint : hand.hand_joints())
    if (joint.allFinite()) {
      sum += joint;
      ++count;
    }
  return count ? Eigen::Vector3d(sum / count) : hand.palm;
}

// Whether every joint lies within `spread_m` of the hand's centre across the glass: a flat hand
// facing it, whose joints all arrive at once. A fist or a pointing hand reaches the glass with
// its knuckles or a fingertip long before its centre would.
bool flat_to_glass(const HandSkeleton& hand, double spread_m) {
  const double centre_z = hand_centre(hand).z();
  for (const Eigen::Vector3d& joint : hand.hand_joints())
    if (joint.allFinite() && std::abs(joint.z() - centre_z) > spread_m) return false;
  return true;
}

// Joints of a flat hand further apart across the glass than this are no palm meeting it.
constexpr double kFlatHandSpreadM = 0.02;

}  // namespace

void check_contact_prediction_parameters(const ContactPredictionParameters& p) {
  auto require = [](bool ok, const std::string& why) {
    if (!ok) throw std::invalid_argument("contact prediction: " + why);
  };
  require(p.history_us >= 20'000, "history must be at least 20 ms (three tracker frames)");
  require(p.max_horizon_us > 0, "the horizon must be positive");
  require(p.max_sample_age_us > 0, "the samples' age limit must be positive");
  require(std::isfinite(p.min_approach_speed_m_s) && p.min_approach_speed_m_s > 0, "the approach speed must be positive");
  require(std::isfinite(p.max_deceleration_m_s2) && p.max_deceleration_m_s2 >= 0, "the deceleration bound must be >= 0");
  require(p.weight_time_constant_us > 0, "the weights' time constant must be positive");
  require(std::isfinite(p.contact_height_m) && p.contact_height_m >= 0 && p.contact_height_m < 0.05,
          "the contact height must be in [0, 5 cm)");
}

ContactPredictionParameters scaled_to_time(const ContactPredictionParameters& p, double time_scale) {
  if (!std::isfinite(time_scale) || time_scale <= 0)
    throw std::invalid_argument("contact prediction: the time scale must be positive");
  auto slower = [&](uint64_t us) { return uint64_t(std::llround(double(us) / time_scale)); };
  ContactPredictionParameters scaled = p;
  // Never shorter than the check allows: a scene played faster than real time still needs three
  // tracker frames to fit.
  scaled.history_us = std::max<uint64_t>(20'000, slower(p.history_us));
  scaled.max_horizon_us = slower(p.max_horizon_us);
  scaled.max_sample_age_us = slower(p.max_sample_age_us);
  scaled.weight_time_constant_us = std::max<uint64_t>(1, slower(p.weight_time_constant_us));
  scaled.min_approach_speed_m_s = p.min_approach_speed_m_s * time_scale;
  scaled.max_deceleration_m_s2 = p.max_deceleration_m_s2 * time_scale * time_scale;
  return scaled;
}

ContactPredictor::ContactPredictor(const ContactPredictionParameters& parameters, const TouchParameters& touch)
    : parameters_(parameters), touch_(touch) {
  check_contact_prediction_parameters(parameters_);
  check_touch_parameters(touch_);
}

void ContactPredictor::add_local(const std::vector<HandSkeleton>& hands) { add(local_, hands); }
void ContactPredictor::add_remote(const std::vector<HandSkeleton>& hands) { add(remote_, hands); }

void ContactPredictor::add(Track& track, const std::vector<HandSkeleton>& hands) {
  // Nearest the glass on either side of it: the other site's hands, mapped into this site's
  // frame, are behind it (z < 0).
  const HandSkeleton* hand = nullptr;
  for (const HandSkeleton& candidate : hands)
    if (std::isfinite(candidate.palm.z()) && (!hand || std::abs(candidate.palm.z()) < std::abs(hand->palm.z())))
      hand = &candidate;
  if (!hand) {
    track.samples.clear();
    return;
  }
  if (!track.samples.empty() && hand->timestamp_us <= track.samples.back().timestamp_us) return;
  track.samples.push_back(*hand);
  while (track.samples.size() > kMaxSamples ||
         track.samples.front().timestamp_us + parameters_.history_us < track.samples.back().timestamp_us)
    track.samples.pop_front();
}

std::optional<ContactPredictor::Reach> ContactPredictor::reach(const Track& track, uint64_t now_us) const {
  if (track.samples.size() < 3) return std::nullopt;
  const HandSkeleton& newest = track.samples.back();
  if (now_us > newest.timestamp_us + parameters_.max_sample_age_us) return std::nullopt;
  // Least squares in time since the newest sample (seconds): the distance to the glass
  // |z| = a + b t + c t^2; x and y linear.
  const int n = int(track.samples.size());
  Eigen::MatrixXd quadratic(n, 3), linear(n, 2);
  Eigen::VectorXd x(n), y(n), z(n);
  for (int i = 0; i < n; ++i) {
    const HandSkeleton& s = track.samples[size_t(i)];
    const double t = (double(s.timestamp_us) - double(newest.timestamp_us)) * 1e-6;
    const double w = std::exp(t / (double(parameters_.weight_time_constant_us) * 1e-6));
    quadratic.row(i) << w, w * t, w * t * t;
    linear.row(i) << w, w * t;
    const Eigen::Vector3d centre = hand_centre(s);
    x(i) = w * centre.x();
    y(i) = w * centre.y();
    z(i) = w * (std::abs(centre.z()) - parameters_.contact_height_m);
  }
  if (!x.allFinite() || !y.allFinite() || !z.allFinite()) return std::nullopt;
  // Samples too close in time to tell a velocity (or all at one instant) fit nothing.
  const double span_s = (double(newest.timestamp_us) - double(track.samples.front().timestamp_us)) * 1e-6;
  if (span_s < 0.015) return std::nullopt;
  const Eigen::Vector3d zfit = quadratic.colPivHouseholderQr().solve(z);
  const Eigen::Vector2d xfit = linear.colPivHouseholderQr().solve(x);
  const Eigen::Vector2d yfit = linear.colPivHouseholderQr().solve(y);
  if (!zfit.allFinite() || !xfit.allFinite() || !yfit.allFinite()) return std::nullopt;
  const double a = zfit(0), b = zfit(1);
  double c = zfit(2);
  // A reach speeds up as it starts and slows towards the glass. A fit that still sees it speeding
  // up is early in the reach, and carrying that on would predict the contact too early, which
  // cannot be taken back once the pulse is felt; its speed alone predicts later.
  c = std::clamp(c, 0.0, 0.5 * parameters_.max_deceleration_m_s2);
  Reach reach;
  double tau = 0;
  if (a <= 0) {
    tau = 0;  // already at the glass
  } else {
    if (b > -parameters_.min_approach_speed_m_s) return std::nullopt;  // not reaching for it
    const std::optional<double> root = first_root_after_now(a, b, c);
    if (!root) return std::nullopt;  // slows to a stop before the glass
    tau = *root;
  }
  const double contact_us = double(newest.timestamp_us) + tau * 1e6;
  if (contact_us > double(now_us) + double(parameters_.max_horizon_us)) return std::nullopt;
  reach.contact_us = uint64_t(std::max(0.0, contact_us));
  // The newest skeleton slid to the fitted position and pressed flat against the glass.
  const Eigen::Vector3d centre = hand_centre(newest);
  const Eigen::Vector3d shift(xfit(0) + xfit(1) * tau - centre.x(), yfit(0) + yfit(1) * tau - centre.y(),
                              std::copysign(parameters_.contact_height_m, centre.z()) - centre.z());
  HandSkeleton moved = newest;
  moved.palm += shift;
  moved.wrist += shift;
  for (auto& digit : moved.digits)
    for (auto& joint : digit) joint += shift;
  moved.timestamp_us = reach.contact_us;
  reach.at_glass = moved;
  return reach;
}

std::optional<uint64_t> ContactPredictor::predicted_contact_us(uint64_t now_us) const {
  const std::optional<Reach> local = reach(local_, now_us), remote = reach(remote_, now_us);
  if (!local || !remote) return std::nullopt;
  const HandSkeleton local_hands[] = {local->at_glass}, remote_hands[] = {remote->at_glass};
  // The fit follows a palm onto the glass; under the hand-mesh rule, which also sees fists and
  // fingertips meet, those touches are not predicted: they pulse their own pattern when seen.
  if (touch_.rule == TouchRule::HandMeshes &&
      (!flat_to_glass(local->at_glass, kFlatHandSpreadM) || !flat_to_glass(remote->at_glass, kFlatHandSpreadM)))
    return std::nullopt;
  if (touch_overlap(local_hands, remote_hands, touch_, &patch_cache_).overlap_area_m2 <= touch_.start_area_m2) return std::nullopt;
  return std::max(local->contact_us, remote->contact_us);
}

}  // namespace rt

