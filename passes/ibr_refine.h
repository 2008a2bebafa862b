#pragma once
// Pass (optional, off by default): plane-sweep refinement of the fused depth
// (shaders/ibr_refine.comp): `hypotheses` depths `step_m` apart around each fused depth, the
// one where the colors of the views that see it (warping's visibility test, with warping's
// tolerance) agree best wins.
// The knob of the accuracy-versus-time table.
//   in:  fused_depth r32f, color rgba8 atlas, points rgba32f atlas (each view's own depth in w),
//        the camera table
//   out: refined_depth r32f
#include "passes/common/ibr_scene.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct RefineSettings {
  int hypotheses = 9;
  // 1 mm: the fused depth is within a few millimetres of the surface (millimetre depth, planar
  // splats), and half a millimetre of depth already moves a stripe by a fraction of a pixel.
  float step_m = 0.001f;
};

class IbrRefinePass {
 public:
  // `visibility`: warping's (WarpSettings::visibility); a view that does not see the point would
  // score the color of whatever hides it.
  IbrRefinePass(vk::Context& context, const RefineSettings& settings = {}, VisibilityTolerance visibility = {});
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& color,
              vk::Image& points, vk::Image& refined_depth, uint32_t view_count) const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage ibr_refine_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& color,
                               const HostImage& points, const RefineSettings& settings = {},
                               VisibilityTolerance visibility = {});

}  // namespace rt::passes
