#include "passes/lumi_upsample.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "passes/lumi_input.h"
#include "shared/lumi_net.h"

#include "lumi_upsample.comp.h"

namespace rt::passes {
namespace {

struct Source {
  uint32_t low, high;
  float t;
};

// The shader's arithmetic, in float.
Source source_of(uint32_t x, uint32_t small_size, uint32_t scale) {
  const float s = std::max((float(x) + 0.5f) / float(scale) - 0.5f, 0.0f);
  const uint32_t low = std::min(uint32_t(s), small_size - 1);
  return {low, std::min(low + 1, small_size - 1), s - float(low)};
}

float mix(float a, float b, float t) { return a * (1.0f - t) + b * t; }

}  // namespace

LumiUpsamplePass::LumiUpsamplePass(vk::Context& context)
    : kernel_(context, "lumi_upsample", lumi_upsample_comp_spirv) {}

void LumiUpsamplePass::add_to(vk::FrameGraph& graph, vk::Buffer& small, vk::Buffer& full, uint32_t width,
                              uint32_t height, uint32_t planes, uint32_t scale) const {
  if (width == 0 || height == 0 || planes == 0 || scale == 0 || scale > 8)
    throw std::invalid_argument("lumi_upsample: a non-empty target, at least one plane, a scale of 1 to 8");
  const uint32_t sw = lumi_small_size(width, scale), sh = lumi_small_size(height, scale);
  if (small.size() < size_t(sw) * sh * planes * sizeof(float) || full.size() < size_t(width) * height * planes * sizeof(float))
    throw std::invalid_argument("lumi_upsample: '" + small.name() + "' or '" + full.name() + "' is smaller than its tensor");
  graph.add_compute_pass({
      .name = "lumi_upsample",
      .kernel = &kernel_,
      .bindings = {{"Small", &small}, {"Full", &full}},
      .threads = {width, height, 1},
      .push_constants = vk::push_constants_from<shader_abi::LumiScaleParams>(
          [=] { return shader_abi::LumiScaleParams{width, height, sw, sh, planes, scale}; }),
  });
}

LumiTensor lumi_upsample_reference(const LumiTensor& small, uint32_t width, uint32_t height, uint32_t scale) {
  LumiTensor out(1, small.channels, width, height);
  for (uint32_t y = 0; y < height; ++y) {
    const Source sy = source_of(y, small.height, scale);
    for (uint32_t x = 0; x < width; ++x) {
      const Source sx = source_of(x, small.width, scale);
      for (uint32_t p = 0; p < small.channels; ++p) {
        const float top = mix(small.at(0, p, sx.low, sy.low), small.at(0, p, sx.high, sy.low), sx.t);
        const float bottom = mix(small.at(0, p, sx.low, sy.high), small.at(0, p, sx.high, sy.high), sx.t);
        out.at(0, p, x, y) = mix(top, bottom, sy.t);
      }
    }
  }
  return out;
}

}  // namespace rt::passes
