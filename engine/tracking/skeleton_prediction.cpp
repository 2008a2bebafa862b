#include "tracking/skeleton_prediction.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rt {
namespace {

struct JointMotion {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
};

// Least squares of p(t) - p(newest) = v t + a t^2 / 2 over the samples (t <= 0, seconds): through
// the newest sample, so a hand at rest stays exactly where it was last seen. Two samples give a
// velocity only; one gives no motion.
JointMotion fit_joint(const std::vector<std::pair<double, Eigen::Vector3d>>& samples, const Eigen::Vector3d& newest) {
  JointMotion motion;
  std::vector<std::pair<double, Eigen::Vector3d>> older;
  for (const auto& [t, p] : samples)
    if (t < 0 && p.allFinite()) older.emplace_back(t, p - newest);
  if (older.empty()) return motion;
  if (older.size() == 1) {
    motion.velocity = older[0].second / older[0].first;
    return motion;
  }
  Eigen::MatrixXd basis(older.size(), 2);
  Eigen::MatrixXd offsets(older.size(), 3);
  for (size_t i = 0; i < older.size(); ++i) {
    basis.row(Eigen::Index(i)) << older[i].first, 0.5 * older[i].first * older[i].first;
    offsets.row(Eigen::Index(i)) = older[i].second.transpose();
  }
  const Eigen::MatrixXd fit = basis.colPivHouseholderQr().solve(offsets);
  if (!fit.allFinite()) return motion;
  motion.velocity = fit.row(0).transpose();
  motion.acceleration = fit.row(1).transpose();
  return motion;
}

Eigen::Vector3d clamp_norm(const Eigen::Vector3d& v, double max) {
  const double n = v.norm();
  return n > max ? Eigen::Vector3d(v * (max / n)) : v;
}

}  // namespace

void check_skeleton_prediction_parameters(const SkeletonPredictionParameters& p) {
  auto require = [](bool ok, const std::string& why) {
    if (!ok) throw std::invalid_argument("skeleton prediction: " + why);
  };
  require(p.history_us > 0, "the history must be positive");
  require(p.acceleration_fade_us > 0, "the acceleration's fade must be positive");
  require(std::isfinite(p.max_speed_m_s) && p.max_speed_m_s >= 0, "the speed limit must be >= 0");
  require(std::isfinite(p.max_acceleration_m_s2) && p.max_acceleration_m_s2 >= 0, "the acceleration limit must be >= 0");
}

std::optional<HandSkeleton> predict_hand(std::span<const HandSkeleton> history, uint64_t at_us,
                                         const SkeletonPredictionParameters& parameters) {
  check_skeleton_prediction_parameters(parameters);
  if (history.empty()) return std::nullopt;
  const HandSkeleton& newest = history.back();
  HandSkeleton predicted = newest;
  const uint64_t lead_us = at_us > newest.timestamp_us ? at_us - newest.timestamp_us : 0;
  const double lead_s = double(std::min(lead_us, parameters.max_lead_us)) * 1e-6;
  predicted.timestamp_us = std::max(at_us, newest.timestamp_us);
  // The acceleration fades as exp(-s / fade): the position it adds over the lead.
  const double fade_s = double(parameters.acceleration_fade_us) * 1e-6;
  const double accelerated = fade_s * (lead_s - fade_s * (1.0 - std::exp(-lead_s / fade_s)));
  std::vector<double> times;
  size_t first = history.size() - 1;
  while (first > 0 && history[first - 1].timestamp_us + parameters.history_us >= newest.timestamp_us &&
         history[first - 1].timestamp_us < history[first].timestamp_us)
    --first;
  for (size_t i = first; i < history.size(); ++i)
    times.push_back((double(history[i].timestamp_us) - double(newest.timestamp_us)) * 1e-6);

  auto carry = [&](auto joint_of) {
    Eigen::Vector3d& out = joint_of(predicted);
    if (!out.allFinite()) return;
    std::vector<std::pair<double, Eigen::Vector3d>> samples;
    for (size_t i = first; i < history.size(); ++i) samples.emplace_back(times[i - first], joint_of(history[i]));
    JointMotion motion = fit_joint(samples, out);
    motion.velocity = clamp_norm(motion.velocity, parameters.max_speed_m_s);
    motion.acceleration = clamp_norm(motion.acceleration, parameters.max_acceleration_m_s2);
    Eigen::Vector3d step;
    for (int k = 0; k < 3; ++k) {
      const double v = motion.velocity(k), a = motion.acceleration(k);
      if (v * a < 0) {
        // Slowing down: it comes to a stop and stays there, rather than turning back.
        const double t = std::min(lead_s, -v / a);
        step(k) = v * t + 0.5 * a * t * t;
      } else {
        step(k) = v * lead_s + a * accelerated;
      }
    }
    out += clamp_norm(step, parameters.max_speed_m_s * lead_s);
    // Never through the glass: the user's side of it is z >= 0.
    out.z() = std::max(out.z(), 0.0);
  };
  // Each joint carried on its own stretches the bones a little where the hand turns; the
  // receiver's shape adaption reads the hand's size from them, so the bones keep the newest
  // sample's lengths, in the directions the joints were carried to.
  auto keep_length = [&](const Eigen::Vector3d& parent, Eigen::Vector3d& joint, const Eigen::Vector3d& newest_parent,
                         const Eigen::Vector3d& newest_joint) {
    if (!joint.allFinite() || !parent.allFinite()) return;
    const double length = (newest_joint - newest_parent).norm();
    const Eigen::Vector3d bone = joint - parent;
    joint = bone.norm() > 1e-9 ? Eigen::Vector3d(parent + bone.normalized() * length) : Eigen::Vector3d(parent);
    joint.z() = std::max(joint.z(), 0.0);
  };
  carry([](auto& hand) -> auto& { return hand.wrist; });
  carry([](auto& hand) -> auto& { return hand.palm; });
  carry([](auto& hand) -> auto& { return hand.elbow; });
  for (int d = 0; d < kDigitCount; ++d)
    for (int j = 0; j < kJointsPerDigit; ++j) carry([d, j](auto& hand) -> auto& { return hand.digits[size_t(d)][size_t(j)]; });
  keep_length(predicted.wrist, predicted.elbow, newest.wrist, newest.elbow);
  for (int d = 0; d < kDigitCount; ++d)
    for (int j = 0; j < kJointsPerDigit; ++j) {
      auto& digit = predicted.digits[size_t(d)];
      const auto& newest_digit = newest.digits[size_t(d)];
      keep_length(j == 0 ? predicted.wrist : digit[size_t(j - 1)], digit[size_t(j)], j == 0 ? newest.wrist : newest_digit[size_t(j - 1)],
                  newest_digit[size_t(j)]);
    }
  return predicted;
}

}  // namespace rt
