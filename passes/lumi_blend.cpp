#include "passes/lumi_blend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "passes/common/reference_math.h"
#include "shared/config.h"
#include "shared/lumi_net.h"

#include "lumi_blend.comp.h"

namespace rt::passes {

LumiBlendPass::LumiBlendPass(vk::Context& context) : kernel_(context, "lumi_blend", lumi_blend_comp_spirv) {}

void LumiBlendPass::add_to(vk::FrameGraph& graph, vk::Image& fused_depth, vk::Image& warped, vk::Image& features,
                           vk::Buffer& blending, vk::Image& portrait, vk::Image& portrait_depth,
                           uint32_t view_count) const {
  const uint32_t w = fused_depth.width(), h = fused_depth.height();
  if (view_count == 0 || view_count > RT_IBR_MAX_VIEWS)
    throw std::invalid_argument("lumi_blend: 1 to " + std::to_string(RT_IBR_MAX_VIEWS) + " views");
  for (const vk::Image* atlas : {&warped, &features})
    if (atlas->width() != w || atlas->height() < h * view_count)
      throw std::invalid_argument("lumi_blend: '" + atlas->name() + "' holds fewer than " + std::to_string(view_count) +
                                  " bands of the target size");
  for (const vk::Image* image : {&portrait, &portrait_depth})
    if (image->width() != w || image->height() != h)
      throw std::invalid_argument("lumi_blend: '" + image->name() + "' differs in size from the fused depth");
  if (blending.size() < size_t(w) * h * (1 + view_count) * sizeof(float))
    throw std::invalid_argument("lumi_blend: '" + blending.name() + "' is smaller than its tensor");
  graph.add_compute_pass({
      .name = "lumi_blend",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth}, {"warped", &warped}, {"features", &features},
                   {"Blending", &blending}, {"portrait", &portrait}, {"portrait_depth", &portrait_depth}},
      .threads = {w, h, 1},
      .push_constants = vk::push_constants_from<shader_abi::LumiTensorParams>(
          [=] { return shader_abi::LumiTensorParams{w, h, view_count, 0, 0}; }),
  });
}

Portrait lumi_blend_reference(const HostImage& fused_depth, const HostImage& warped, const HostImage& features,
                              const LumiTensor& blending, uint32_t view_count) {
  const uint32_t w = fused_depth.width, h = fused_depth.height;
  Portrait out{HostImage(w, h, PixelFormat::RGBA32F), HostImage(w, h, PixelFormat::R32F)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float weighted[3] = {}, plain[3] = {}, weight_sum = 0.0f;
      int seeing = 0;
      for (uint32_t v = 0; v < view_count; ++v) {
        const float* f = &features.texels[features.index(x, y + v * h)];
        if (!(f[3] > 0.0f) || !(f[2] > 0.0f) || !std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
          continue;
        const float* raw_color = &warped.texels[warped.index(x, y + v * h)];
        const float raw = blending.at(0, 1 + v, x, y);
        const float weight = std::isfinite(raw) ? std::max(raw, 0.0f) : 0.0f;
        for (int i = 0; i < 3; ++i) {
          const float c = unit_or_zero(raw_color[i]);
          weighted[i] += weight * c;
          plain[i] += c;
        }
        weight_sum += weight;
        ++seeing;
      }
      if (seeing == 0) continue;
      float* p = &out.color.texels[out.color.index(x, y)];
      for (int i = 0; i < 3; ++i)
        p[i] = unit_or_zero(weight_sum > 1e-6f ? weighted[i] / weight_sum : plain[i] / float(seeing));
      p[3] = unit_or_zero(blending.at(0, 0, x, y));
      const float z = fused_depth.at(x, y);
      out.depth.at(x, y) = std::isfinite(z) && z > 0.0f ? z : 0.0f;
    }
  return out;
}

}  // namespace rt::passes
