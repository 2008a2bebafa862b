#pragma once
// The truth of the remote user's hand and forearm in a target view, for the evaluations of the
// dual hand: the hand reaching for the glass and its forearm rasterized alone, as the simulator
// draws them, to find where the scene's ground truth shows them (evaluation/hand_region.h).
#include "evaluation/hand_region.h"
#include "evaluation/touch_phase.h"
#include "geometry/camera.h"
#include "passes/person_raster.h"
#include "sim/person_pose.h"

namespace rt::pipeline {

struct LimbTruth {
  evaluation::HandRegion region;
  HandSkeleton hand;  // the measured hand, true joints
  double distance_m = 0;  // of its averaged joints to the screen
  std::optional<evaluation::TouchPhase> phase;
};

class LimbTruthRenderer {
 public:
  LimbTruthRenderer(vk::Context& context, const Camera& view);
  // scene_*: the simulator's ground truth of the same view and pose (target_color, _depth_m, _part).
  LimbTruth measure(const sim::PersonPose& pose, const sim::UserAppearance& user, const HostImage& scene_color,
                    const HostImage& scene_depth, const HostImage& scene_part);

 private:
  vk::Context& context_;
  uint32_t width_, height_;
  passes::RasterViewParams view_;
  passes::PersonRasterPass raster_;
  vk::Buffer mesh_;
  uint32_t vertices_ = 0;
  vk::Image color_, depth_, part_, depth_buffer_;
  vk::FrameGraph graph_;
};

}  // namespace rt::pipeline
