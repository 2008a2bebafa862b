#pragma once
// The simulated hand tracker: samples the synthetic user's hands at 50 Hz, keeps those inside
// its tracking range, converts them into its own space (millimetres, Leap axes) and applies the
// tracker effects the scene asks for (jitter, latency, dropouts), each drawing from its own
// random stream derived from the scene's seed, so a scene always gives the same frames.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "geometry/site_frames.h"
#include "sim/effects.h"
#include "sim/hand_tracker.h"
#include "sim/scene.h"
#include "sim/site_description.h"

namespace rt::sim {

inline constexpr double kTrackerRateHz = 50.0;
inline constexpr uint64_t kTrackerPeriodUs = 20'000;
// The device reports positions in micrometre steps and directions in steps of 1e-6 (about the
// precision of the float32 numbers a real one sends); this also keeps tracker.jsonl lines short.
inline constexpr double kPositionStepMm = 1e-3;
inline constexpr double kDirectionStep = 1e-6;

// A hand in front of the device, as it truly is, in the site frame.
struct SyntheticHand {
  HandSkeleton skeleton;
  double palm_width_m = 0.085;
  double arm_width_m = std::numeric_limits<double>::quiet_NaN();  // NaN: the device reports no armWidth
};
// The hands at a time (seconds since the scene started; may be negative under latency).
using HandSource = std::function<std::vector<SyntheticHand>(double t_s)>;

// Two-state Markov chain: tracked <-> lost. From the long-run lost fraction p and the mean
// burst length m: a burst ends with probability 1/m per frame, starts with p/(m (1 - p)).
class DropoutProcess {
 public:
  // Throws std::invalid_argument if no chain has this fraction and burst length (p > m / (m + 1)).
  DropoutProcess(const TrackerDropouts& dropouts, std::seed_seq& seed);
  bool next_frame_lost();

 private:
  std::mt19937_64 random_;
  std::bernoulli_distribution start_, end_;
  bool lost_ = false;
};

class SimulatedHandTracker : public HandTracker {
 public:
  SimulatedHandTracker(HandSource source, const TrackerPlacement& placement, const TrackerEffects& effects,
                       uint64_t seed, uint64_t frame_count);
  std::optional<TrackerFrame> next_frame() override;

 private:
  void add_jitter(TrackerHand& hand);

  HandSource source_;
  TrackerPlacement placement_;
  TrackerEffects effects_;
  uint64_t frame_count_;
  uint64_t next_index_ = 0;
  std::optional<std::mt19937_64> jitter_random_;
  std::optional<DropoutProcess> dropouts_;
  // Leap keeps a hand's id while it stays tracked and gives it a new one when it comes back.
  int32_t next_hand_id_ = 1;
  std::array<std::optional<int32_t>, 2> tracked_id_;  // right, left
};

// The user of `site` in `scene`, sampled for the scene's whole duration.
SimulatedHandTracker make_simulated_tracker(const Scene& scene, Site site);
uint64_t tracker_frame_count(const Scene& scene);

}  // namespace rt::sim
