#include "passes/ibr_resolve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "passes/common/reference_math.h"

#include "ibr_resolve.comp.h"

namespace rt::passes {
namespace {

uint32_t checked_factor(uint32_t factor) {
  if (factor < 2 || factor > 4) throw std::invalid_argument("portrait resolve: factor must be 2..4");
  return factor;
}

}  // namespace

IbrResolvePass::IbrResolvePass(vk::Context& context, uint32_t factor)
    : factor_(checked_factor(factor)), kernel_(context, "ibr_resolve", ibr_resolve_comp_spirv, {{"factor", int32_t(factor)}}) {}

void IbrResolvePass::add_to(vk::FrameGraph& graph, vk::Image& fine_portrait, vk::Image& fine_depth, vk::Image& portrait,
                            vk::Image& portrait_depth) const {
  const uint32_t w = portrait.width(), h = portrait.height();
  if (portrait_depth.width() != w || portrait_depth.height() != h)
    throw std::invalid_argument("ibr_resolve: the portrait and its depth differ in size");
  for (const vk::Image* fine : {&fine_portrait, &fine_depth})
    if (fine->width() != w * factor_ || fine->height() != h * factor_)
      throw std::invalid_argument("ibr_resolve: '" + fine->name() + "' is not " + std::to_string(factor_) +
                                  " times the portrait's size");
  graph.add_compute_pass({
      .name = "ibr_resolve",
      .kernel = &kernel_,
      .bindings = {{"fine_portrait", &fine_portrait}, {"fine_depth", &fine_depth}, {"portrait", &portrait},
                   {"portrait_depth", &portrait_depth}},
      .threads = {w, h, 1},
  });
}

Portrait ibr_resolve_reference(const HostImage& fine_portrait, const HostImage& fine_depth, uint32_t factor) {
  checked_factor(factor);
  if (fine_portrait.width % factor || fine_portrait.height % factor || fine_depth.width != fine_portrait.width ||
      fine_depth.height != fine_portrait.height)
    throw std::invalid_argument("ibr_resolve: the fine images are not factor times one size");
  const uint32_t w = fine_portrait.width / factor, h = fine_portrait.height / factor;
  Portrait out{HostImage(w, h, PixelFormat::RGBA32F, 0.0f), HostImage(w, h, PixelFormat::R32F, 0.0f)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float premultiplied[3] = {0, 0, 0}, coverage = 0, nearest = 0;
      for (uint32_t dy = 0; dy < factor; ++dy)
        for (uint32_t dx = 0; dx < factor; ++dx) {
          const uint32_t fx = x * factor + dx, fy = y * factor + dy;
          const float a = fine_portrait.at(fx, fy, 3);
          const float alpha = a > 0.0f ? std::min(a, 1.0f) : 0.0f;
          for (uint32_t c = 0; c < 3; ++c) premultiplied[c] += unit_or_zero(fine_portrait.at(fx, fy, c)) * alpha;
          coverage += alpha;
          const float z = fine_depth.at(fx, fy);
          if (std::isfinite(z) && z > 0.0f && (nearest == 0.0f || z < nearest)) nearest = z;
        }
      const float centre = fine_depth.at(x * factor + factor / 2, y * factor + factor / 2);
      if (std::isfinite(centre) && centre > 0.0f) nearest = centre;
      for (uint32_t c = 0; c < 3; ++c) out.color.at(x, y, c) = coverage > 0.0f ? unit_or_zero(premultiplied[c] / coverage) : 0.0f;
      out.color.at(x, y, 3) = coverage / float(factor * factor);
      out.depth.at(x, y) = nearest;
    }
  return out;
}

}  // namespace rt::passes
