#include "passes/depth_outliers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "depth_outliers.comp.h"

namespace rt::passes {
namespace {

const DepthOutliersSettings& checked_outlier_settings(const DepthOutliersSettings& s) {
  if (!(s.max_step_mm >= 0.0f) || !(s.max_step_relative >= 0.0f) || !std::isfinite(s.max_step_mm) ||
      !std::isfinite(s.max_step_relative) || s.min_support < 0 || s.min_support > 8)
    throw std::invalid_argument("depth_outliers: needs finite max_step_mm >= 0 and max_step_relative >= 0, and "
                                "min_support from 0 to 8 (of a pixel's eight neighbours)");
  return s;
}

// What the GPU reads from an uploaded R16U texel (host_image.cpp's packing).
uint32_t stored_millimetres(float texel) {
  if (std::isnan(texel)) return 0;
  return uint32_t(std::lround(std::clamp(texel, 0.0f, 65535.0f)));
}

}  // namespace

DepthOutliersPass::DepthOutliersPass(vk::Context& context, const DepthOutliersSettings& settings)
    : kernel_(context, "depth_outliers", depth_outliers_comp_spirv,
              {{"max_step_mm", checked_outlier_settings(settings).max_step_mm},
               {"max_step_relative", settings.max_step_relative},
               {"min_support", int32_t(settings.min_support)}}) {}

void DepthOutliersPass::add_to(vk::FrameGraph& graph, vk::Image& depth_mm, vk::Image& filtered_mm,
                               const std::string& pass_name) const {
  if (depth_mm.width() != filtered_mm.width() || depth_mm.height() != filtered_mm.height())
    throw std::invalid_argument(pass_name + ": the filtered image must have the depth image's size");
  graph.add_compute_pass({.name = pass_name,
                          .kernel = &kernel_,
                          .bindings = {{"depth_mm", &depth_mm}, {"filtered_mm", &filtered_mm}},
                          .threads = {depth_mm.width(), depth_mm.height(), 1}});
}

HostImage depth_outliers_reference(const HostImage& depth_mm, const DepthOutliersSettings& settings) {
  checked_outlier_settings(settings);
  if (depth_mm.format != PixelFormat::R16U) throw std::invalid_argument("depth_outliers: the depth image must be r16u");
  const int w = int(depth_mm.width), h = int(depth_mm.height);
  std::vector<uint32_t> mm(depth_mm.texels.size());
  std::transform(depth_mm.texels.begin(), depth_mm.texels.end(), mm.begin(), stored_millimetres);
  HostImage out(depth_mm.width, depth_mm.height, PixelFormat::R16U, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t z = mm[size_t(y) * w + x];
      if (z == 0) continue;
      const float step = std::max(settings.max_step_mm, settings.max_step_relative * float(z));
      int support = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const uint32_t n = mm[size_t(qy) * w + qx];
          if (n != 0 && std::abs(float(n) - float(z)) <= step) ++support;
        }
      if (support >= settings.min_support) out.texels[size_t(y) * w + x] = float(z);
    }
  return out;
}

}  // namespace rt::passes
