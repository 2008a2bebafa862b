#pragma once
// Pass: the arithmetic peak kernel (shaders/fma_peak.comp), against which the benchmarks set a
// compute-bound pass (pipeline/roofline.h).
//   in:  seeds, one float per invocation (non-finite counts as 0, clamped to [-1, 1])
//   out: sums, one float per invocation: the sum of its chains after `iterations` steps of
//        x -> fma(x, 0.999, 0.001)
#include <vector>

#include "vulkan/frame_graph.h"

namespace rt::passes {

class FmaPeakPass {
 public:
  explicit FmaPeakPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Buffer& seeds, vk::Buffer& sums, uint32_t invocations, uint32_t iterations,
              const std::string& pass_name = "fma_peak") const;

 private:
  vk::ComputeKernel kernel_;
};

// The floating-point operations one run does (a fused multiply-add counts as two).
double fma_peak_flops(uint32_t invocations, uint32_t iterations);

// The plain C++ reference.
std::vector<float> fma_peak_reference(const std::vector<float>& seeds, uint32_t iterations);

}  // namespace rt::passes
