#pragma once
// The paper's mode: the viewpoint computed once at the start of a call and kept (it assumes the
// seated viewer's head stays put). Robust over several frames: frames without eyes are skipped,
// the estimate is the median of the frames' midpoints, frames far from it are dropped as
// outliers, and the remaining frames must agree.
#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "viewer/eye_pair.h"

namespace rt {

struct InitialViewpointOptions {
  // Half a second at the cameras' 30 fps: enough to outvote a few wrong detections.
  size_t frames_needed = 15;
  // A frame's midpoint further than this from the median is a wrong detection, not head motion:
  // a still-seated head sways by about a centimetre.
  double outlier_distance_m = 0.03;
  // The frames kept must agree to this RMS distance; more means the viewer is moving and a
  // one-off viewpoint would be wrong soon (use the continuous tracker then).
  double max_spread_m = 0.015;
};

struct InitialViewpoint {
  ViewerFailure failure = ViewerFailure::None;
  std::string message;
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();  // site frame; meaningful only when ok()
  double spread_m = 0.0;         // RMS distance of the frames kept from the estimate
  size_t frames_used = 0;
  size_t frames_outliers = 0;
  size_t frames_without_eyes = 0;
  uint64_t timestamp_us = 0;     // of the newest frame used
  bool ok() const { return failure == ViewerFailure::None; }
};

class InitialViewpointEstimator {
 public:
  explicit InitialViewpointEstimator(const InitialViewpointOptions& options = {});

  // Every frame counts, failed ones too (as frames without eyes).
  void add(uint64_t timestamp_us, const EyePair& frame);
  // TooFewFrames until `frames_needed` frames agree; Unsteady when they spread too far.
  InitialViewpoint result() const;

 private:
  struct Sample {
    uint64_t timestamp_us = 0;
    Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();
  };
  InitialViewpointOptions options_;
  std::vector<Sample> samples_;
  size_t frames_without_eyes_ = 0;
};

}  // namespace rt
