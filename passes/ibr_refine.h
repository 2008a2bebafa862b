#pragma once
// Pass (optional, off by default): plane-sweep refinement of the fused depth
// (shaders/ibr_refine.comp): `hypotheses` depths `step_m` apart around each fused depth, the
// one where the views' colours agree best wins. The knob of the accuracy-versus-time table.
//   in:  fused_depth r32f, colour rgba8 atlas, the camera table
//   out: refined_depth r32f
#include "passes/ibr_scene.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct RefineSettings {
  int hypotheses = 9;
  float step_m = 0.004f;
};

class IbrRefinePass {
 public:
  IbrRefinePass(vk::Context& context, const RefineSettings& settings = {});
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& colour,
              vk::Image& refined_depth, uint32_t view_count) const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage ibr_refine_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& colour,
                               const RefineSettings& settings = {});

}  // namespace rt::passes
