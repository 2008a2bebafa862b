#include "passes/composite.h"

#include <cmath>
#include <stdexcept>

#include "passes/common/reference_math.h"

#include "composite.comp.h"

namespace rt::passes {
CompositePass::CompositePass(vk::Context& context) : kernel_(context, "composite", composite_comp_spirv) {}

void CompositePass::add_to(vk::FrameGraph& graph, vk::Image& fused, vk::Image& background, vk::Image& display,
                           const std::string& pass_name) const {
  for (const vk::Image* image : {&fused, &background})
    if (image->width() != display.width() || image->height() != display.height())
      throw std::invalid_argument(pass_name + ": '" + image->name() + "' differs in size from '" + display.name() + "'");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"fused", &fused}, {"background", &background}, {"display", &display}},
      .threads = {display.width(), display.height(), 1},
  });
}

HostImage composite_reference(const HostImage& fused, const HostImage& background) {
  HostImage display(fused.width, fused.height, PixelFormat::RGBA8);
  for (uint32_t y = 0; y < fused.height; ++y)
    for (uint32_t x = 0; x < fused.width; ++x) {
      const float a_f = unit_or_zero(fused.at(x, y, 3));
      for (uint32_t c = 0; c < 3; ++c) {
        const float premultiplied = std::min(unit_or_zero(fused.at(x, y, c)), a_f);
        const float value = premultiplied + unit_or_zero(background.at(x, y, c)) * (1.0f - a_f);
        display.at(x, y, c) = std::round(std::min(value, 1.0f) * 255.0f) / 255.0f;
      }
      display.at(x, y, 3) = 1.0f;
    }
  return display;
}

}  // namespace rt::passes
