#pragma once
// The ceilings a benchmark sets its passes against, measured on the same device in the same run:
// bandwidth (the best of a transfer copy of a buffer, a storage-buffer copy kernel, an rgba32f
// storage-image copy kernel and a host memcpy, each moving the same bytes) and arithmetic (chains
// of fused multiply-adds). A pass's fraction of the roofline is its bytes moved per second over
// the best bandwidth; a compute-bound pass's is its FLOP/s over the peak.
#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

#include "vulkan/context.h"

namespace rt::pipeline {

struct Roofline {
  uint64_t bytes = 0;             // each copy reads this many and writes this many
  double buffer_transfer_gbps = 0;  // vkCmdCopyBuffer
  double buffer_kernel_gbps = 0;    // passes::BufferCopyPass
  double image_kernel_gbps = 0;     // passes::CopyPass, rgba32f
  double host_memcpy_gbps = 0;      // std::memcpy on this machine's CPU
  double peak_gflops = 0;           // passes::FmaPeakPass

  double best_gbps() const;
  std::string best_name() const;
  // A pass's achieved bandwidth as a fraction of the best (0 when unmeasured).
  double fraction(double gbps) const { return best_gbps() > 0 ? gbps / best_gbps() : 0.0; }
  nlohmann::json to_json() const;
  std::string describe() const;  // a few lines for a benchmark's output
};

// Runs each ceiling `frames` times (after one warm-up) and takes the medians. `bytes` is rounded
// down to whole 16-byte elements and whole rows of a square-ish rgba32f image.
Roofline measure_roofline(vk::Context& context, uint64_t bytes = 64ull << 20, uint32_t frames = 5);

}  // namespace rt::pipeline

namespace rt::vk {
struct PassTiming;
}

namespace rt::pipeline {

// Floating-point operations a frame of a pass does, by pass name, where the benchmark counts them.
using PassFlops = std::map<std::string, double>;

// vk::format_profile's table with each pass's bandwidth as a percentage of the roofline and,
// for the passes in `flops`, its GFLOP/s as a percentage of the arithmetic peak.
std::string format_profile(const std::vector<vk::PassTiming>& timings, const Roofline& roofline,
                           const PassFlops& flops = {});
// Per pass: GPU ms, GB/s and the fraction of the roofline (and GFLOP/s and the fraction of the
// peak where counted), for a benchmark's JSON.
nlohmann::json timings_against_roofline(const std::vector<vk::PassTiming>& timings, const Roofline& roofline,
                                        const PassFlops& flops = {});

}  // namespace rt::pipeline
