#pragma once
// The continuous mode (not in the paper, which fixes the viewpoint once): the viewpoint follows
// the viewer's head for motion parallax. Each frame's eye midpoint passes two gates, then a
// One-Euro filter:
//  - a reprojection gate: the views must agree on the eyes;
//  - a jump gate: the head cannot have moved faster than a person moves since the last accepted
//    frame. If the viewer really did jump (or the track was wrong), several rejected frames in a
//    row that agree with each other re-acquire the track there.
// Timestamps are microseconds of a monotonic clock; out-of-order and repeated ones are ignored.
#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

#include "viewer/eye_pair.h"
#include "viewer/one_euro_filter.h"

namespace rt {

struct ViewpointTrackerOptions {
  OneEuroParameters smoothing;
  // Seated head motion stays below ~1 m/s even in quick leans; 1.5 leaves headroom.
  double max_speed_m_per_s = 1.5;
  // Measurement noise and filter lag on top of the motion: a few millimetres of triangulation
  // jitter plus about a centimetre of lag at brisk speed.
  double jump_allowance_m = 0.02;
  // Same meaning as MultiViewLimits::max_reprojection_error_mrad; applies to EyePair updates.
  double max_reprojection_mrad = 10.0;
  // This many consecutive rejected frames that agree with each other move the track there:
  // a sixth of a second at 30 fps, longer than a wrong detection usually persists.
  size_t reacquire_after = 5;
  // A midpoint must lie in front of the screen by more than this (site z, metres); as in
  // MultiViewLimits, no seated viewer's eye comes within 5 cm of the panel.
  double min_distance_to_screen_m = 0.05;
};

enum class TrackerVerdict {
  Started,               // first measurement: the track begins here
  Accepted,              // filtered into the track
  Reacquired,            // consistent rejected frames moved the track
  RejectedJump,          // farther from the track than the head could have moved
  RejectedReprojection,  // the views disagreed
  RejectedInvalid,       // NaN, or not in front of the screen
  NotFound,              // the frame had no eyes; the track keeps its last value
  IgnoredOutOfOrder,     // timestamp older than one already seen
  IgnoredDuplicate,      // timestamp equal to one already seen
};

const char* verdict_name(TrackerVerdict verdict);

struct TrackedViewpoint {
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();          // site frame, filtered
  Eigen::Vector3d velocity_m_per_s = Eigen::Vector3d::Zero();  // filtered
  uint64_t timestamp_us = 0;                                   // of the last accepted frame
};

class ViewpointTracker {
 public:
  explicit ViewpointTracker(const ViewpointTrackerOptions& options = {});

  TrackerVerdict update(uint64_t timestamp_us, const EyePair& measurement);
  // A midpoint from elsewhere (a replay, another detector); `reprojection_mrad` 0 if unknown.
  TrackerVerdict update(uint64_t timestamp_us, const Eigen::Vector3d& midpoint, double reprojection_mrad = 0.0);

  // Empty until the first accepted frame.
  std::optional<TrackedViewpoint> latest() const;
  // True when no frame was accepted within `timeout_us` before `now_us` (or none ever was).
  bool lost(uint64_t now_us, uint64_t timeout_us) const;

 private:
  struct Candidate {
    uint64_t timestamp_us = 0;
    Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();
  };
  bool timestamp_is_new(uint64_t timestamp_us, TrackerVerdict& ignored);
  double gate_m(uint64_t from_us, uint64_t to_us) const;

  ViewpointTrackerOptions options_;
  OneEuroFilter filter_;
  std::optional<uint64_t> newest_timestamp_us_;
  uint64_t accepted_timestamp_us_ = 0;
  std::vector<Candidate> rejected_run_;
};

}  // namespace rt
