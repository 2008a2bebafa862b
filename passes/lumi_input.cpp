#include "passes/lumi_input.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "passes/common/reference_math.h"
#include "shared/config.h"
#include "shared/lumi_net.h"

#include "lumi_input.comp.h"

namespace rt::passes {

uint32_t lumi_small_size(uint32_t full, uint32_t scale) { return (full + scale - 1) / scale; }

LumiInputPass::LumiInputPass(vk::Context& context) : kernel_(context, "lumi_input", lumi_input_comp_spirv) {}

void LumiInputPass::add_to(vk::FrameGraph& graph, vk::Image& warped, vk::Image& features, vk::Buffer& inputs,
                           vk::Buffer& coverage, uint32_t width, uint32_t height, uint32_t view_count,
                           uint32_t scale) const {
  if (view_count == 0 || view_count > RT_IBR_MAX_VIEWS || scale == 0 || scale > 8 || width == 0 || height == 0)
    throw std::invalid_argument("lumi_input: 1 to " + std::to_string(RT_IBR_MAX_VIEWS) +
                                " views, a scale of 1 to 8 and a non-empty target");
  for (const vk::Image* atlas : {&warped, &features})
    if (atlas->width() != width || atlas->height() < height * view_count)
      throw std::invalid_argument("lumi_input: '" + atlas->name() + "' holds fewer than " + std::to_string(view_count) +
                                  " bands of the target size");
  const uint32_t sw = lumi_small_size(width, scale), sh = lumi_small_size(height, scale);
  const size_t plane = size_t(sw) * sh * view_count * sizeof(float);
  if (inputs.size() < plane * RT_LUMI_INPUT_CHANNELS || coverage.size() < plane)
    throw std::invalid_argument("lumi_input: '" + inputs.name() + "' or '" + coverage.name() +
                                "' is smaller than its tensor at 1/" + std::to_string(scale) + " resolution");
  graph.add_compute_pass({
      .name = "lumi_input",
      .kernel = &kernel_,
      .bindings = {{"warped", &warped}, {"features", &features}, {"Inputs", &inputs}, {"Coverage", &coverage}},
      .threads = {sw, sh, view_count},
      .push_constants = vk::push_constants_from<shader_abi::LumiScaleParams>([=] {
        return shader_abi::LumiScaleParams{width, height, sw, sh, view_count, scale};
      }),
  });
}

LumiInputs lumi_input_reference(const HostImage& warped, const HostImage& features, uint32_t height,
                                uint32_t view_count, uint32_t scale) {
  const uint32_t width = warped.width, sw = lumi_small_size(width, scale), sh = lumi_small_size(height, scale);
  LumiInputs out{LumiTensor(view_count, RT_LUMI_INPUT_CHANNELS, sw, sh), LumiTensor(view_count, 1, sw, sh)};
  for (uint32_t v = 0; v < view_count; ++v)
    for (uint32_t cy = 0; cy < sh; ++cy)
      for (uint32_t cx = 0; cx < sw; ++cx) {
        float values[RT_LUMI_INPUT_CHANNELS] = {};
        int seen = 0, pixels = 0;
        for (uint32_t y = cy * scale; y < std::min(height, (cy + 1) * scale); ++y)
          for (uint32_t x = cx * scale; x < std::min(width, (cx + 1) * scale); ++x) {
            ++pixels;
            const float* f = &features.texels[features.index(x, y + v * height)];
            if (!(f[3] > 0.0f) || !(f[2] > 0.0f) || !std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
              continue;
            const float* c = &warped.texels[warped.index(x, y + v * height)];
            ++seen;
            for (int i = 0; i < 3; ++i) values[i] += unit_or_zero(c[i]);
            values[4] += std::max(f[0], 0.0f);
            values[5] += std::max(f[1], 0.0f);
            values[6] += f[2];
          }
        if (seen > 0)
          for (float& value : values) value /= float(seen);
        values[3] = float(seen) / float(std::max(pixels, 1));
        for (uint32_t c = 0; c < RT_LUMI_INPUT_CHANNELS; ++c) out.inputs.at(v, c, cx, cy) = values[c];
        out.coverage.at(v, 0, cx, cy) = values[3];
      }
  return out;
}

}  // namespace rt::passes
