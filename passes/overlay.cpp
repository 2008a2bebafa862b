#include "passes/overlay.h"

#include <cmath>
#include <stdexcept>

#include "passes/common/reference_math.h"

#include "overlay.comp.h"

namespace rt::passes {
OverlayPass::OverlayPass(vk::Context& context) : kernel_(context, "overlay", overlay_comp_spirv) {}

void OverlayPass::add_to(vk::FrameGraph& graph, vk::Image& hand_color, vk::Image& hand_alpha, vk::Image& portrait,
                         vk::Image& fused, const std::string& pass_name) const {
  for (const vk::Image* image : {&hand_color, &hand_alpha, &portrait})
    if (image->width() != fused.width() || image->height() != fused.height())
      throw std::invalid_argument(pass_name + ": '" + image->name() + "' differs in size from '" + fused.name() + "'");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"hand_color", &hand_color}, {"hand_alpha", &hand_alpha}, {"portrait", &portrait}, {"fused", &fused}},
      .threads = {fused.width(), fused.height(), 1},
  });
}

HostImage overlay_reference(const HostImage& hand_color, const HostImage& hand_alpha, const HostImage& portrait) {
  HostImage fused(portrait.width, portrait.height, PixelFormat::RGBA32F);
  for (uint32_t y = 0; y < portrait.height; ++y)
    for (uint32_t x = 0; x < portrait.width; ++x) {
      const float a_g = unit_or_zero(hand_alpha.at(x, y));
      const float a_i = unit_or_zero(portrait.at(x, y, 3));
      const float a_f = a_g + a_i * (1.0f - a_g);
      for (uint32_t c = 0; c < 3; ++c) {
        const float c_g = unit_or_zero(hand_color.at(x, y, c));
        const float c_i = unit_or_zero(portrait.at(x, y, c));
        // Eq. 5 as printed, then premultiplied; alpha_f = 0 leaves the color at 0.
        const float c_f = a_f > 0.0f ? (c_g * a_g + c_i * a_i * (1.0f - a_g)) / a_f : 0.0f;
        fused.at(x, y, c) = c_f * a_f;
      }
      fused.at(x, y, 3) = a_f;
    }
  return fused;
}

}  // namespace rt::passes
