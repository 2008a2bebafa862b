#include "passes/ibr_blend.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "passes/common/reference_math.h"

#include "ibr_blend.comp.h"

namespace rt::passes {

const BlendSettings& checked_blend_settings(const BlendSettings& s) {
  if (s.best_views < 2 || s.best_views > RT_IBR_MAX_VIEWS + 1 || !(s.resolution_weight >= 0.0f))
    throw std::invalid_argument("blending: best_views (k) must be 2.." + std::to_string(RT_IBR_MAX_VIEWS + 1) +
                                " and resolution_weight >= 0");
  return s;
}

IbrBlendPass::IbrBlendPass(vk::Context& context, const BlendSettings& settings)
    : kernel_(context, "ibr_blend", ibr_blend_comp_spirv,
              {{"best_views", int32_t(checked_blend_settings(settings).best_views)},
               {"resolution_weight", settings.resolution_weight}}) {}

void IbrBlendPass::add_to(vk::FrameGraph& graph, vk::Image& fused_depth, vk::Image& warped, vk::Image& features,
                          vk::Image& portrait, vk::Image& portrait_depth, uint32_t view_count) const {
  const uint32_t w = fused_depth.width(), h = fused_depth.height();
  if (view_count == 0 || view_count > RT_IBR_MAX_VIEWS)
    throw std::invalid_argument("ibr_blend: 1 to " + std::to_string(RT_IBR_MAX_VIEWS) + " views");
  for (const vk::Image* atlas : {&warped, &features})
    if (atlas->width() != w || atlas->height() < h * view_count)
      throw std::invalid_argument("ibr_blend: '" + atlas->name() + "' holds fewer than " + std::to_string(view_count) +
                                  " bands of the target size");
  for (const vk::Image* image : {&portrait, &portrait_depth})
    if (image->width() != w || image->height() != h)
      throw std::invalid_argument("ibr_blend: '" + image->name() + "' differs in size from the fused depth");
  graph.add_compute_pass({
      .name = "ibr_blend",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth}, {"warped", &warped}, {"features", &features},
                   {"portrait", &portrait}, {"portrait_depth", &portrait_depth}},
      .threads = {w, h, 1},
      .push_constants = vk::push_constants_from<shader_abi::IbrBlendParams>(
          [view_count] { return shader_abi::IbrBlendParams{view_count}; }),
  });
}

Portrait ibr_blend_reference(const HostImage& fused_depth, const HostImage& warped, const HostImage& features,
                             uint32_t view_count, const BlendSettings& s) {
  const uint32_t w = fused_depth.width, h = fused_depth.height;
  Portrait out{HostImage(w, h, PixelFormat::RGBA32F), HostImage(w, h, PixelFormat::R32F)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      std::array<float, RT_IBR_MAX_VIEWS> penalty{}, feather{};
      penalty.fill(-1.0f);
      int candidates = 0;
      float largest = 0.0f;
      for (uint32_t v = 0; v < view_count; ++v) {
        const float* f = &features.texels[features.index(x, y + v * h)];
        if (!(f[3] > 0.0f) || !(f[2] > 0.0f) || !std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
          continue;
        penalty[v] = std::max(f[0], 0.0f) + s.resolution_weight * std::max(f[1], 0.0f);
        feather[v] = f[2];
        largest = std::max(largest, penalty[v]);
        ++candidates;
      }
      if (candidates == 0) continue;
      // The k-th smallest penalty, ties broken by view index as in the shader.
      float threshold = largest * 1.0001f + 1e-6f;
      if (candidates >= s.best_views)
        for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
          if (penalty[size_t(v)] < 0.0f) continue;
          int below = 0;
          for (int u = 0; u < RT_IBR_MAX_VIEWS; ++u)
            if (penalty[size_t(u)] >= 0.0f && (penalty[size_t(u)] < penalty[size_t(v)] ||
                                               (penalty[size_t(u)] == penalty[size_t(v)] && u < v)))
              ++below;
          if (below == s.best_views - 1) threshold = penalty[size_t(v)];
        }
      std::array<float, 3> sum{};
      float weight_sum = 0.0f, best_penalty = 1e30f;
      std::array<float, 3> best{};
      for (uint32_t v = 0; v < view_count; ++v) {
        if (penalty[v] < 0.0f) continue;
        const float* raw = &warped.texels[warped.index(x, y + v * h)];
        const float c[3] = {unit_or_zero(raw[0]), unit_or_zero(raw[1]), unit_or_zero(raw[2])};
        const float weight = threshold > 0.0f ? std::max(0.0f, 1.0f - penalty[v] / threshold) * feather[v] : feather[v];
        for (int i = 0; i < 3; ++i) sum[size_t(i)] += weight * c[i];
        weight_sum += weight;
        if (penalty[v] < best_penalty) {
          best_penalty = penalty[v];
          best = {c[0], c[1], c[2]};
        }
      }
      float* p = &out.color.texels[out.color.index(x, y)];
      for (int i = 0; i < 3; ++i)
        p[i] = unit_or_zero(weight_sum > 1e-6f ? sum[size_t(i)] / weight_sum : best[size_t(i)]);
      p[3] = 1.0f;
      const float z = fused_depth.at(x, y);
      out.depth.at(x, y) = std::isfinite(z) && z > 0.0f ? z : 0.0f;
    }
  return out;
}

double ulr_blend_flops(uint64_t candidates, uint64_t covered_pixels) {
  // Per candidate: its penalty (a multiply-add), its weight (a division, a subtraction and a
  // multiplication), the weighted colour (three multiply-adds) and the weight sum (an addition).
  constexpr double kPerCandidate = 2 + 3 + 6 + 1;
  // Per covered pixel: the threshold (a multiply-add) and the normalisation (three divisions).
  constexpr double kPerCoveredPixel = 2 + 3;
  return kPerCandidate * double(candidates) + kPerCoveredPixel * double(covered_pixels);
}

}  // namespace rt::passes
