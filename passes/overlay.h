#pragma once
// Pass: the geometry hand layer over the image-based portrait layer (paper Eq. 5).
//   in:  hand_color rgba32f (c_g, straight), hand_alpha r32f (alpha_g), portrait rgba32f (c_i, alpha_i, straight)
//   out: fused rgba32f, premultiplied: (c_f alpha_f, alpha_f), so (0, 0, 0, 0) where alpha_f = 0.
// Non-finite inputs count as 0; colors and alphas are clamped to [0, 1].
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class OverlayPass {
 public:
  explicit OverlayPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Image& hand_color, vk::Image& hand_alpha, vk::Image& portrait,
              vk::Image& fused, const std::string& pass_name = "overlay") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference, written as the paper's equation with its division, guarded.
HostImage overlay_reference(const HostImage& hand_color, const HostImage& hand_alpha, const HostImage& portrait);

}  // namespace rt::passes
