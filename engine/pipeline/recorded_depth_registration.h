#pragma once
// A recorded site's cameras made fit for the image-based model, which samples colour and depth
// along the same rays: a camera whose depth lens is apart from its colour lens (every real k4a
// device) gets its flying pixels and lone outliers removed (passes/depth_outliers.h: a
// time-of-flight sensor's, which the simulator's aligned cameras do not have) and its depth
// registered into its colour image (DepthRegistration), and its model's
// depth camera becomes the colour camera. Cameras recorded already aligned (the simulator's) are
// left as they are, at no cost.
#include <memory>
#include <vector>

#include "passes/common/ibr_scene.h"
#include "pipeline/depth_registration.h"
#include "sim/recorded_rgbd_source.h"

namespace rt::pipeline {

class RecordedDepthRegistration {
 public:
  RecordedDepthRegistration(vk::Context& context, const std::vector<sim::RecordedRgbdSource::RecordedIntrinsics>& cameras);

  // How many cameras are registered.
  size_t registered_count() const;
  // The models the image-based model then takes: a registered camera's depth is its colour camera.
  std::vector<passes::IbrCameraModel> models(std::vector<passes::IbrCameraModel> recorded) const;
  // Replaces each registered camera's depth by its depth in colour. Runs GPU work: the caller
  // holds the GPU turn where there is one.
  void apply(std::vector<sim::RgbdImage>& cameras);
  // GPU ms per registered camera (median), 0 when none is registered.
  double median_ms() const;

 private:
  std::vector<std::unique_ptr<DepthRegistration>> registrations_;  // null where aligned
};

}  // namespace rt::pipeline
