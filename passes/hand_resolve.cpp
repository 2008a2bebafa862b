#include "passes/hand_resolve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hand_resolve.comp.h"
#include "passes/common/reference_math.h"

namespace rt::passes {

uint32_t check_hand_supersampling(uint32_t factor) {
  if (factor < 1 || factor > 4)
    throw std::invalid_argument("the hand's supersampling must be 1 to 4 samples a side, got " + std::to_string(factor));
  return factor;
}

HandResolvePass::HandResolvePass(vk::Context& context, uint32_t factor)
    : factor_(check_hand_supersampling(factor)),
      kernel_(context, "hand_resolve", hand_resolve_comp_spirv, {{"factor", int32_t(factor)}}) {}

void HandResolvePass::add_to(vk::FrameGraph& graph, const HandLayerImages& fine, const HandLayerImages& resolved,
                             const std::string& pass_name) const {
  const uint32_t w = resolved.color->width(), h = resolved.color->height();
  for (const vk::Image* image : {fine.color, fine.mask, fine.depth_m})
    if (image->width() != w * factor_ || image->height() != h * factor_)
      throw std::invalid_argument(pass_name + ": '" + image->name() + "' is not " + std::to_string(factor_) + " x " +
                                  std::to_string(w) + "x" + std::to_string(h));
  for (const vk::Image* image : {resolved.mask, resolved.depth_m})
    if (image->width() != w || image->height() != h)
      throw std::invalid_argument(pass_name + ": '" + image->name() + "' differs in size from the resolved color");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"fine_color", fine.color}, {"fine_mask", fine.mask}, {"fine_depth_m", fine.depth_m},
                   {"color", resolved.color}, {"mask", resolved.mask}, {"depth_m", resolved.depth_m}},
      .threads = {w, h, 1},
  });
}

HandLayers hand_resolve_reference(const HostImage& fine_color, const HostImage& fine_mask, const HostImage& fine_depth_m,
                                  uint32_t factor) {
  check_hand_supersampling(factor);
  const uint32_t w = fine_color.width / factor, h = fine_color.height / factor;
  HandLayers out{HostImage(w, h, PixelFormat::RGBA32F), HostImage(w, h, PixelFormat::R32F), HostImage(w, h, PixelFormat::R32F)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float sum[3] = {0, 0, 0}, coverage = 0, nearest = 0;
      for (uint32_t dy = 0; dy < factor; ++dy)
        for (uint32_t dx = 0; dx < factor; ++dx) {
          const uint32_t sx = x * factor + dx, sy = y * factor + dy;
          const float covered = unit_or_zero(fine_mask.at(sx, sy));
          for (uint32_t c = 0; c < 3; ++c) {
            const float value = fine_color.at(sx, sy, c);
            sum[c] += covered * (std::isfinite(value) ? value : 0.0f);
          }
          coverage += covered;
          const float z = fine_depth_m.at(sx, sy);
          if (covered > 0 && std::isfinite(z) && z > 0 && (nearest == 0 || z < nearest)) nearest = z;
        }
      if (coverage > 0) {
        for (uint32_t c = 0; c < 3; ++c) out.color.at(x, y, c) = sum[c] / coverage;
        out.color.at(x, y, 3) = 1.0f;
      }
      out.mask.at(x, y) = coverage / float(factor * factor);
      out.depth_m.at(x, y) = nearest;
    }
  return out;
}

}  // namespace rt::passes
