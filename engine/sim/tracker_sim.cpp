#include "sim/tracker_sim.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "sim/motion.h"
#include "sim/person_mesh.h"
#include "sim/tracker_space.h"

namespace rt::sim {

namespace {

// Random streams, one per effect and site, so that turning one effect on does not change the
// draws of another.
enum class Stream : uint32_t { TrackerJitter = 1, TrackerDropouts = 2 };

std::seed_seq seed_for(uint64_t seed, Stream stream) {
  return std::seed_seq{uint32_t(seed), uint32_t(seed >> 32), uint32_t(stream)};
}

double quantise(double value, double step) { return std::round(value / step) * step; }

void quantise(Eigen::Vector3d& v, double step) {
  for (int i = 0; i < 3; ++i) v[i] = quantise(v[i], step);
}

void quantise(TrackerHand& hand) {
  for (Eigen::Vector3d* p : {&hand.palm_position, &hand.wrist}) quantise(*p, kPositionStepMm);
  if (hand.elbow) quantise(*hand.elbow, kPositionStepMm);
  for (TrackerDigit& digit : hand.digits)
    for (Eigen::Vector3d* p : {&digit.carp, &digit.mcp, &digit.pip, &digit.dip, &digit.btip, &digit.tip})
      quantise(*p, kPositionStepMm);
  quantise(hand.palm_normal, kDirectionStep);
  quantise(hand.direction, kDirectionStep);
  if (hand.palm_width) hand.palm_width = quantise(*hand.palm_width, kPositionStepMm);
  if (hand.arm_width) hand.arm_width = quantise(*hand.arm_width, kPositionStepMm);
}

}  // namespace

DropoutProcess::DropoutProcess(const TrackerDropouts& dropouts, std::seed_seq& seed) : random_(seed) {
  const double p = dropouts.probability, m = dropouts.mean_length_frames;
  if (!(p >= 0 && p < 1) || !(m >= 1))
    throw std::invalid_argument("tracker_dropouts: probability must be in [0, 1) and mean_length_frames >= 1");
  const double end = 1.0 / m;
  const double start = p * end / (1.0 - p);
  if (start > 1.0)
    throw std::invalid_argument("tracker_dropouts: a lost fraction of " + std::to_string(p) +
                                " needs bursts longer than " + std::to_string(m) + " frames (at most m / (m + 1))");
  start_ = std::bernoulli_distribution(start);
  end_ = std::bernoulli_distribution(end);
}

bool DropoutProcess::next_frame_lost() {
  lost_ = lost_ ? !end_(random_) : start_(random_);
  return lost_;
}

SimulatedHandTracker::SimulatedHandTracker(HandSource source, const TrackerPlacement& placement,
                                           const TrackerEffects& effects, uint64_t seed, uint64_t frame_count)
    : source_(std::move(source)), placement_(placement), effects_(effects), frame_count_(frame_count) {
  if (!source_) throw std::invalid_argument("simulated tracker needs a hand source");
  if (effects_.jitter) {
    std::seed_seq sequence = seed_for(seed, Stream::TrackerJitter);
    jitter_random_.emplace(sequence);
  }
  if (effects_.dropouts) {
    std::seed_seq sequence = seed_for(seed, Stream::TrackerDropouts);
    dropouts_.emplace(*effects_.dropouts, sequence);
  }
}

void SimulatedHandTracker::add_jitter(TrackerHand& hand) {
  std::normal_distribution<double> noise(0.0, effects_.jitter->sigma_mm);
  auto shake = [&](Eigen::Vector3d& p) {
    for (int i = 0; i < 3; ++i) p[i] += noise(*jitter_random_);
  };
  shake(hand.palm_position);
  shake(hand.wrist);
  if (hand.elbow) shake(*hand.elbow);
  for (int d = 0; d < kDigitCount; ++d) {
    TrackerDigit& digit = hand.digits[d];
    // The thumb's metacarpal keeps zero length and the fingertip stays the distal bone's end:
    // the tracker's hand model holds those, whatever its noise.
    if (d != int(Digit::Thumb)) shake(digit.carp);
    shake(digit.mcp);
    if (d == int(Digit::Thumb)) digit.carp = digit.mcp;
    shake(digit.pip);
    shake(digit.dip);
    shake(digit.tip);
    digit.btip = digit.tip;
  }
}

std::optional<TrackerFrame> SimulatedHandTracker::next_frame() {
  if (next_index_ >= frame_count_) return std::nullopt;
  TrackerFrame frame;
  frame.id = int64_t(next_index_) + 1;
  frame.timestamp_us = next_index_ * kTrackerPeriodUs;
  ++next_index_;

  // Advanced on every frame, so the pattern of losses does not depend on where the hands are.
  const bool lost = dropouts_ && dropouts_->next_frame_lost();
  double sample_s = frame.timestamp_us * 1e-6;
  if (effects_.latency) sample_s -= effects_.latency->ms * 1e-3;

  std::array<bool, 2> seen{false, false};
  for (const SyntheticHand& synthetic : source_(sample_s)) {
    const int side = synthetic.skeleton.is_left ? 1 : 0;
    if (lost || seen[side] || !placement_.sees(synthetic.skeleton.palm)) continue;
    seen[side] = true;
    if (!tracked_id_[side]) tracked_id_[side] = next_hand_id_++;
    TrackerHand hand = tracker_hand_from_skeleton(synthetic.skeleton, synthetic.palm_width_m, synthetic.arm_width_m, placement_);
    hand.id = *tracked_id_[side];
    if (effects_.jitter) add_jitter(hand);
    quantise(hand);
    frame.hands.push_back(hand);
  }
  for (int side = 0; side < 2; ++side)
    if (!seen[side]) tracked_id_[side].reset();
  return frame;
}

uint64_t tracker_frame_count(const Scene& scene) {
  return uint64_t(std::floor(scene.duration_s() * kTrackerRateHz + 1e-9));
}

SimulatedHandTracker make_simulated_tracker(const Scene& scene, Site site) {
  const SiteSetup& setup = scene.at(site);
  auto track = std::make_shared<const MotionTrack>(make_motion_track(scene, site));
  const double palm_width = palm_width_m(setup.user.hand_scale);
  HandSource source = [track, palm_width](double t_s) {
    const PersonPose pose = track->pose_at(t_s);
    return std::vector<SyntheticHand>{{pose.right_hand, palm_width, kArmWidthM}, {pose.left_hand, palm_width, kArmWidthM}};
  };
  // Each site's tracker draws from its own streams.
  const uint64_t site_seed = scene.seed * 2 + (site == Site::A ? 0 : 1);
  return SimulatedHandTracker(std::move(source), setup.site.tracker, scene.effects.tracker, site_seed,
                              tracker_frame_count(scene));
}

}  // namespace rt::sim
