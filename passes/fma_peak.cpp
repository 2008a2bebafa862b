#include "passes/fma_peak.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "shared/config.h"

#include "fma_peak.comp.h"

namespace rt::passes {

FmaPeakPass::FmaPeakPass(vk::Context& context) : kernel_(context, "fma_peak", fma_peak_comp_spirv) {}

void FmaPeakPass::add_to(vk::FrameGraph& graph, vk::Buffer& seeds, vk::Buffer& sums, uint32_t invocations,
                         uint32_t iterations, const std::string& pass_name) const {
  const uint64_t bytes = uint64_t(invocations) * sizeof(float);
  if (bytes > seeds.size() || bytes > sums.size())
    throw std::invalid_argument(pass_name + ": " + std::to_string(invocations) + " invocations need " + std::to_string(bytes) +
                                " bytes in '" + seeds.name() + "' and '" + sums.name() + "'");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"Seeds", &seeds}, {"Sums", &sums}},
      .threads = {std::max(invocations, 1u), 1, 1},
      .push_constants = vk::push_constants_from<shader_abi::FmaPeakParams>(
          [invocations, iterations] { return shader_abi::FmaPeakParams{invocations, iterations}; }),
  });
}

double fma_peak_flops(uint32_t invocations, uint32_t iterations) {
  return double(invocations) * iterations * RT_FMA_CHAINS * 4 * 2;
}

std::vector<float> fma_peak_reference(const std::vector<float>& seeds, uint32_t iterations) {
  std::vector<float> sums(seeds.size());
  for (size_t index = 0; index < seeds.size(); ++index) {
    const float seed = std::isfinite(seeds[index]) ? std::clamp(seeds[index], -1.0f, 1.0f) : 0.0f;
    float total = 0.0f;
    float lanes[4] = {0, 0, 0, 0};
    for (int c = 0; c < RT_FMA_CHAINS; ++c) {
      for (int lane = 0; lane < 4; ++lane) {
        float x = seed + 0.125f * float(lane) * float(c + 1) / float(RT_FMA_CHAINS);
        for (uint32_t i = 0; i < iterations; ++i) x = std::fma(x, 0.999f, 0.001f);
        lanes[lane] += x;
      }
    }
    total = lanes[0] + lanes[1] + lanes[2] + lanes[3];
    sums[index] = total;
  }
  return sums;
}

}  // namespace rt::passes
