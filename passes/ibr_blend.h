#pragma once
// Pass: unstructured lumigraph blending (Buehler et al. 2001) into the portrait
// (shaders/ibr_blend.comp). The blending stage of the image-based model: it reads only the
// warped views and their features, so a learned blending (Lumi-Net) can replace it.
//   in:  fused_depth r32f, warped and features rgba32f atlases (ibr_warp), view_count bands
//   out: portrait rgba32f (straight color, alpha 1 where a view sees the surface, else 0),
//        portrait_depth r32f (metres, 0 = nothing)
#include "passes/common/ibr_scene.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct BlendSettings {
  int best_views = 3;              // k: the k-1 best views blend, the k-th has weight 0
  float resolution_weight = 1.0f;  // radians of penalty per metre of resolution penalty
};
// `s`, or std::invalid_argument saying which setting is out of range.
const BlendSettings& checked_blend_settings(const BlendSettings& s);

class IbrBlendPass {
 public:
  IbrBlendPass(vk::Context& context, const BlendSettings& settings = {});
  void add_to(vk::FrameGraph& graph, vk::Image& fused_depth, vk::Image& warped, vk::Image& features,
              vk::Image& portrait, vk::Image& portrait_depth, uint32_t view_count) const;

 private:
  vk::ComputeKernel kernel_;
};

struct Portrait {
  HostImage color;  // rgba32f, straight alpha
  HostImage depth;   // r32f metres
};
Portrait ibr_blend_reference(const HostImage& fused_depth, const HostImage& warped, const HostImage& features,
                             uint32_t view_count, const BlendSettings& settings = {});

// The lumigraph blend's floating-point operations for a frame with `candidates` visible view
// samples over `covered_pixels` pixels (counted as passes::WarpWork::flops counts).
double ulr_blend_flops(uint64_t candidates, uint64_t covered_pixels);

}  // namespace rt::passes
