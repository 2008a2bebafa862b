#include "passes/lumi_pool.h"

#include <algorithm>
#include <stdexcept>

#include "shared/config.h"
#include "shared/lumi_net.h"

#include "lumi_pool.comp.h"

namespace rt::passes {
namespace {

uint32_t check(uint32_t channels) {
  if (channels == 0) throw std::invalid_argument("lumi_pool: at least one channel");
  return channels;
}

}  // namespace

LumiPoolPass::LumiPoolPass(vk::Context& context, uint32_t channels)
    : channels_(check(channels)), kernel_(context, "lumi_pool", lumi_pool_comp_spirv, {{"channels", int32_t(channels)}}) {}

void LumiPoolPass::add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, vk::Buffer& coverage,
                          vk::Buffer& result, uint32_t width, uint32_t height, uint32_t views) const {
  const size_t plane = size_t(width) * height * views * sizeof(float);
  if (plane == 0 || views > RT_IBR_MAX_VIEWS) throw std::invalid_argument("lumi_pool: empty tensor or too many views");
  if (source.size() < plane * channels_ || coverage.size() < plane || result.size() < plane * 3 * channels_)
    throw std::invalid_argument("lumi_pool: '" + source.name() + "', '" + coverage.name() + "' or '" + result.name() +
                                "' is smaller than its tensor");
  graph.add_compute_pass({
      .name = name,
      .kernel = &kernel_,
      .bindings = {{"Source", &source}, {"Coverage", &coverage}, {"Result", &result}},
      .threads = {width, height, 1},
      .push_constants = vk::push_constants_from<shader_abi::LumiTensorParams>(
          [=] { return shader_abi::LumiTensorParams{width, height, views, 0, 0}; }),
  });
}

LumiTensor lumi_pool_reference(const LumiTensor& source, const LumiTensor& coverage) {
  const uint32_t c_count = source.channels;
  LumiTensor out(source.views, 3 * c_count, source.width, source.height);
  for (uint32_t y = 0; y < source.height; ++y)
    for (uint32_t x = 0; x < source.width; ++x) {
      int seeing = 0;
      for (uint32_t v = 0; v < source.views; ++v) seeing += coverage.at(v, 0, x, y) > 0.0f;
      for (uint32_t c = 0; c < c_count; ++c) {
        float sum = 0.0f, largest = 0.0f;
        bool first = true;
        for (uint32_t v = 0; v < source.views; ++v) {
          const float value = source.at(v, c, x, y);
          out.at(v, c, x, y) = value;
          if (!(coverage.at(v, 0, x, y) > 0.0f)) continue;
          sum += value;
          largest = first ? value : std::max(largest, value);
          first = false;
        }
        const float mean = seeing > 0 ? sum / float(seeing) : 0.0f;
        for (uint32_t v = 0; v < source.views; ++v) {
          out.at(v, c_count + c, x, y) = mean;
          out.at(v, 2 * c_count + c, x, y) = largest;
        }
      }
    }
  return out;
}

}  // namespace rt::passes
