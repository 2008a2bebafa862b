#include "passes/lumi_softmax.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "passes/common/lumi_numeric.h"
#include "shared/config.h"
#include "shared/lumi_net.h"

#include "lumi_softmax.comp.h"

namespace rt::passes {

LumiSoftmaxPass::LumiSoftmaxPass(vk::Context& context) : kernel_(context, "lumi_softmax", lumi_softmax_comp_spirv) {}

void LumiSoftmaxPass::add_to(vk::FrameGraph& graph, vk::Buffer& logits, vk::Buffer& coverage, vk::Buffer& blending,
                             uint32_t width, uint32_t height, uint32_t views) const {
  const size_t plane = size_t(width) * height * sizeof(float);
  if (plane == 0 || views == 0 || views > RT_IBR_MAX_VIEWS)
    throw std::invalid_argument("lumi_softmax: a non-empty tensor of 1 to " + std::to_string(RT_IBR_MAX_VIEWS) + " views");
  if (logits.size() < plane * views * RT_LUMI_HEAD_CHANNELS || coverage.size() < plane * views ||
      blending.size() < plane * (1 + views))
    throw std::invalid_argument("lumi_softmax: '" + logits.name() + "', '" + coverage.name() + "' or '" +
                                blending.name() + "' is smaller than its tensor");
  graph.add_compute_pass({
      .name = "lumi_softmax",
      .kernel = &kernel_,
      .bindings = {{"Logits", &logits}, {"Coverage", &coverage}, {"Blending", &blending}},
      .threads = {width, height, 1},
      .push_constants = vk::push_constants_from<shader_abi::LumiTensorParams>(
          [=] { return shader_abi::LumiTensorParams{width, height, views, 0, 0}; }),
  });
}

LumiTensor lumi_softmax_reference(const LumiTensor& logits, const LumiTensor& coverage) {
  if (logits.channels != RT_LUMI_HEAD_CHANNELS) throw std::invalid_argument("lumi_softmax_reference: 2 channels");
  const uint32_t views = logits.views;
  LumiTensor out(1, 1 + views, logits.width, logits.height);
  for (uint32_t y = 0; y < logits.height; ++y)
    for (uint32_t x = 0; x < logits.width; ++x) {
      std::array<float, RT_IBR_MAX_VIEWS> logit{}, weight{};
      std::array<bool, RT_IBR_MAX_VIEWS> counted{}, sees{};
      int seeing = 0, in_softmax = 0, alpha_terms = 0;
      float largest = 0.0f, alpha_sum = 0.0f;
      for (uint32_t v = 0; v < views; ++v) {
        sees[v] = coverage.at(v, 0, x, y) > 0.0f;
        if (!sees[v]) continue;
        ++seeing;
        const float alpha_logit = logits.at(v, 1, x, y);
        if (!std::isnan(alpha_logit)) alpha_sum += alpha_logit, ++alpha_terms;
        const float l = logits.at(v, 0, x, y);
        if (std::isnan(l) || l == -INFINITY) continue;
        logit[v] = std::min(l, float(RT_LUMI_MAX_LOGIT));
        largest = in_softmax == 0 ? logit[v] : std::max(largest, logit[v]);
        counted[v] = true;
        ++in_softmax;
      }
      float sum = 0.0f;
      for (uint32_t v = 0; v < views; ++v) {
        weight[v] = in_softmax > 0 ? (counted[v] ? std::exp(logit[v] - largest) : 0.0f) : (sees[v] ? 1.0f : 0.0f);
        sum += weight[v];
      }
      float alpha = 0.0f;
      if (seeing > 0 && alpha_terms > 0) {
        const float mean = alpha_sum / float(alpha_terms);
        alpha = std::isnan(mean) ? 0.0f : lumi_safe_sigmoid(mean);
      }
      out.at(0, 0, x, y) = alpha;
      for (uint32_t v = 0; v < views; ++v) out.at(0, 1 + v, x, y) = sum > 0.0f ? weight[v] / sum : 0.0f;
    }
  return out;
}

}  // namespace rt::passes
