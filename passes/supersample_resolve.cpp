#include "passes/supersample_resolve.h"

#include <stdexcept>
#include <string>

#include "supersample_resolve.comp.h"

namespace rt::passes {
namespace {

uint32_t check_factor(uint32_t factor) {
  if (factor < 1 || factor > 7 || factor % 2 == 0)
    throw std::invalid_argument("supersampling factor must be odd, 1 to 7 (the centre sample is the pixel centre), got " +
                                std::to_string(factor));
  return factor;
}

}  // namespace

SupersampleResolvePass::SupersampleResolvePass(vk::Context& context, uint32_t factor)
    : factor_(check_factor(factor)),
      kernel_(context, "supersample_resolve", supersample_resolve_comp_spirv, {{"factor", int32_t(factor)}}) {}

void SupersampleResolvePass::add_to(vk::FrameGraph& graph, const ResolveImages& fine, const ResolveImages& resolved,
                                    const std::string& pass_name) const {
  const uint32_t w = resolved.color->width(), h = resolved.color->height();
  for (const vk::Image* image : {fine.color, fine.depth_m, fine.part})
    if (image->width() != w * factor_ || image->height() != h * factor_)
      throw std::invalid_argument(pass_name + ": '" + image->name() + "' is not " + std::to_string(factor_) + " x " +
                                  std::to_string(w) + "x" + std::to_string(h));
  for (const vk::Image* image : {resolved.depth_m, resolved.part})
    if (image->width() != w || image->height() != h)
      throw std::invalid_argument(pass_name + ": '" + image->name() + "' differs in size from the resolved color");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"fine_color", fine.color}, {"fine_depth_m", fine.depth_m}, {"fine_part", fine.part},
                   {"color", resolved.color}, {"depth_m", resolved.depth_m}, {"part", resolved.part}},
      .threads = {w, h, 1},
  });
}

HostImage supersample_resolve_reference(const HostImage& fine, uint32_t factor) {
  check_factor(factor);
  const uint32_t w = fine.width / factor, h = fine.height / factor;
  HostImage out(w, h, fine.format);
  const uint32_t channels = fine.channels();
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (uint32_t c = 0; c < channels; ++c) {
        if (fine.format == PixelFormat::RGBA8) {
          float sum = 0.0f;
          for (uint32_t dy = 0; dy < factor; ++dy)
            for (uint32_t dx = 0; dx < factor; ++dx) sum += fine.at(x * factor + dx, y * factor + dy, c);
          out.at(x, y, c) = sum / float(factor * factor);
        } else {
          out.at(x, y, c) = fine.at(x * factor + factor / 2, y * factor + factor / 2, c);
        }
      }
  return out;
}

}  // namespace rt::passes
