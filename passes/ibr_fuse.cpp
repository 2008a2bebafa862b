#include "passes/ibr_fuse.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#include "ibr_fuse.comp.h"

namespace rt::passes {
namespace {

const FuseSettings& check(const FuseSettings& s) {
  if (s.fill_min_neighbours < 1 || s.fill_min_neighbours > 9 || !(s.fill_tolerance_m >= 0.0f))
    throw std::invalid_argument("depth fusion: fill_min_neighbours must be 1..9 (9 = no filling), fill_tolerance_m >= 0");
  return s;
}

}  // namespace

IbrFusePass::IbrFusePass(vk::Context& context, const FuseSettings& settings)
    : kernel_(context, "ibr_fuse", ibr_fuse_comp_spirv,
              {{"average_fusion", check(settings).fusion == DepthFusion::Average},
               {"fill_min_neighbours", int32_t(settings.fill_min_neighbours)},
               {"fill_tolerance_m", settings.fill_tolerance_m}}) {}

void IbrFusePass::add_to(vk::FrameGraph& graph, vk::Buffer& fusion, vk::Image& fused_depth) const {
  if (fusion.size() != fusion_buffer_desc(fused_depth.width(), fused_depth.height()).size)
    throw std::invalid_argument("ibr_fuse: the fusion buffer does not match the target size " +
                                std::to_string(fused_depth.width()) + "x" + std::to_string(fused_depth.height()));
  graph.add_compute_pass({
      .name = "ibr_fuse",
      .kernel = &kernel_,
      .bindings = {{"Fusion", &fusion}, {"fused_depth", &fused_depth}},
      .threads = {fused_depth.width(), fused_depth.height(), 1},
  });
}

HostImage ibr_fuse_reference(const std::vector<uint32_t>& fusion, uint32_t width, uint32_t height,
                             const FuseSettings& s) {
  const size_t n = size_t(width) * height;
  auto resolved = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= int(width) || y >= int(height)) return 0.0f;
    const size_t index = size_t(y) * width + size_t(x);
    const uint32_t bits = fusion[index];
    if (bits == RT_IBR_EMPTY_DEPTH_BITS) return 0.0f;
    if (s.fusion == DepthFusion::Average && fusion[2 * n + index] > 0)
      return float(fusion[n + index]) * 1e-5f / float(fusion[2 * n + index]);
    return std::bit_cast<float>(bits);
  };
  HostImage depth(width, height, PixelFormat::R32F);
  for (int y = 0; y < int(height); ++y)
    for (int x = 0; x < int(width); ++x) {
      float z = resolved(x, y);
      if (z == 0.0f) {
        int count = 0;
        float sum = 0.0f, nearest = 1e30f, farthest = 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const float neighbour = resolved(x + dx, y + dy);
            if (neighbour <= 0.0f) continue;
            ++count;
            sum += neighbour;
            nearest = std::min(nearest, neighbour);
            farthest = std::max(farthest, neighbour);
          }
        if (count >= s.fill_min_neighbours && farthest - nearest <= s.fill_tolerance_m) z = sum / float(count);
      }
      depth.at(uint32_t(x), uint32_t(y)) = z;
    }
  return depth;
}

}  // namespace rt::passes
