#pragma once
// Pass: appearance adaption of the skin texture (paper Eq. 3), T -> T' with the running
// statistics: per L-alpha-beta channel c' = min(sigma_i / max(sigma_g, floor), max_contrast)
// (c - m_g) + m_i, back to RGB, clamped to [0, 1]. Until statistics exist T' = T; non-finite
// results keep T. max_contrast (a specialization constant) caps how far the template's texture
// detail is stretched: the portrait's spread is mostly shading, which an unlit mesh lacks.
//   in:  template_texture rgba32f (T), state (AppearanceState)
//   out: adapted_texture rgba32f (T'), alpha copied
#include "image/host_image.h"
#include "shared/config.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::AppearanceState;
inline constexpr float kSigmaFloor = 0.01f;  // L-alpha-beta units: below this a channel is flat
inline constexpr float kMaxContrast = 1.5f;

class HandColorTransferPass {
 public:
  // Throws std::invalid_argument unless max_contrast > 0.
  explicit HandColorTransferPass(vk::Context& context, float max_contrast = kMaxContrast);
  void add_to(vk::FrameGraph& graph, vk::Image& template_texture, vk::Buffer& state, vk::Image& adapted_texture,
              float sigma_floor = kSigmaFloor, const std::string& pass_name = "hand_color_transfer") const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage color_transfer_reference(const HostImage& template_texture, const AppearanceState& state, float sigma_floor,
                                   float max_contrast = kMaxContrast);

}  // namespace rt::passes
