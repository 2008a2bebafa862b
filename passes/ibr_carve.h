#pragma once
// Pass (optional, off by default): see-through carving of the fused depth
// (shaders/ibr_carve.comp). A fused point that some view looks straight through (its own depth
// farther beyond warping's tolerance, at four probes 0.35 texel around the projection) is
// empty space; the pixel takes the nearest surface behind it that such a view observes (the
// target ray marched onto that view's depth), if some view sees that surface. It reopens finger
// gaps narrower than a depth pixel, which the splats of the fingers cover.
//   in:  fused_depth r32f, points rgba32f atlas (site xyz, each view's own depth in w), the camera table
//   out: carved_depth r32f
#include "passes/common/ibr_scene.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct CarveSettings {
  // The see-through probes' offset around the projection, in depth texels: far enough to reach
  // past the gap's own edge, near enough to stay on the finger (tuned with eval ibr; the record
  // is in docs/image-based-model.md).
  float probe_texels = 0.35f;
  int march_steps = 3;         // of the ray onto the see-through view's depth
};

class IbrCarvePass {
 public:
  // `visibility`: warping's (WarpSettings::visibility), for both the see-through test and the
  // check that some view sees the surface behind.
  IbrCarvePass(vk::Context& context, const CarveSettings& settings = {}, VisibilityTolerance visibility = {});
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& points,
              vk::Image& carved_depth, uint32_t view_count) const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage ibr_carve_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& points,
                              const CarveSettings& settings = {}, VisibilityTolerance visibility = {});

}  // namespace rt::passes
