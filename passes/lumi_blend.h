#pragma once
// Pass: the portrait from the warped views and Lumi-Net's upsampled weights and alpha
// (shaders/lumi_blend.comp): weights renormalised over the views that see the pixel (equal where
// they are all 0), alpha the network's; where no view sees the point, alpha 0 and depth 0.
//   in:  fused_depth r32f, warped and features rgba32f atlases (ibr_warp), blending tensor
//        (1, 1 + views, h, w) at the target's resolution (lumi_upsample)
//   out: portrait rgba32f (straight color, alpha), portrait_depth r32f (metres, 0 = nothing)
#include "passes/common/lumi_tensor.h"
#include "passes/ibr_blend.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class LumiBlendPass {
 public:
  explicit LumiBlendPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Image& fused_depth, vk::Image& warped, vk::Image& features,
              vk::Buffer& blending, vk::Image& portrait, vk::Image& portrait_depth, uint32_t view_count) const;

 private:
  vk::ComputeKernel kernel_;
};

Portrait lumi_blend_reference(const HostImage& fused_depth, const HostImage& warped, const HostImage& features,
                              const LumiTensor& blending, uint32_t view_count);

}  // namespace rt::passes
