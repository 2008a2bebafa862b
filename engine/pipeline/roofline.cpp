#include "pipeline/roofline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "passes/buffer_copy.h"
#include "passes/copy.h"
#include "passes/fma_peak.h"
#include "vulkan/frame_graph.h"

namespace rt::pipeline {
namespace {

// Enough arithmetic that the kernel runs for milliseconds, not microseconds, on either kind of
// device: a GPU has thousands of lanes, lavapipe a few dozen.
uint32_t peak_invocations(const vk::Context& context) { return context.is_cpu_device() ? (1u << 16) : (1u << 24); }
constexpr uint32_t kPeakIterations = 256;

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

double host_memcpy_gbps(uint64_t bytes, uint32_t frames) {
  std::vector<std::byte> source(bytes, std::byte{1}), destination(bytes);
  std::vector<double> seconds;
  for (uint32_t i = 0; i <= frames; ++i) {
    const auto start = std::chrono::steady_clock::now();
    std::memcpy(destination.data(), source.data(), bytes);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (i > 0) seconds.push_back(s);  // the first touches fresh pages
    source[i % bytes] = destination[(i * 7919) % bytes];  // the copies are used: none is skipped
  }
  const double s = median(seconds);
  return s > 0 ? 2.0 * double(bytes) / s / 1e9 : 0.0;
}

}  // namespace

double Roofline::best_gbps() const {
  return std::max({buffer_transfer_gbps, buffer_kernel_gbps, image_kernel_gbps, host_memcpy_gbps});
}

std::string Roofline::best_name() const {
  const double best = best_gbps();
  if (best == buffer_transfer_gbps) return "buffer transfer copy";
  if (best == buffer_kernel_gbps) return "buffer copy kernel";
  if (best == image_kernel_gbps) return "image copy kernel";
  return "host memcpy";
}

nlohmann::json Roofline::to_json() const {
  return {{"bytes_each_way", bytes},
          {"buffer_transfer_gbps", buffer_transfer_gbps},
          {"buffer_kernel_gbps", buffer_kernel_gbps},
          {"image_kernel_gbps", image_kernel_gbps},
          {"host_memcpy_gbps", host_memcpy_gbps},
          {"best_gbps", best_gbps()},
          {"best", best_name()},
          {"peak_gflops", peak_gflops}};
}

std::string Roofline::describe() const {
  char text[512];
  std::snprintf(text, sizeof text,
                "roofline (%.0f MB each way, GB/s read plus written): buffer transfer %.2f, buffer kernel %.2f, "
                "rgba32f image kernel %.2f, host memcpy %.2f; best %.2f (%s); FMA peak %.1f GFLOP/s\n",
                double(bytes) / 1e6, buffer_transfer_gbps, buffer_kernel_gbps, image_kernel_gbps, host_memcpy_gbps,
                best_gbps(), best_name().c_str(), peak_gflops);
  return text;
}

Roofline measure_roofline(vk::Context& context, uint64_t bytes, uint32_t frames) {
  Roofline roofline;
  const uint32_t side = std::max<uint32_t>(1, uint32_t(std::sqrt(double(bytes / 16))));
  roofline.bytes = uint64_t(side) * side * 16;  // the same bytes for all four copies
  vk::Buffer source(context, {"roofline source", roofline.bytes});
  vk::Buffer destination(context, {"roofline destination", roofline.bytes});
  vk::Buffer transfer_destination(context, {"roofline transfer destination", roofline.bytes});
  vk::Image image_source(context, {"roofline image source", side, side, PixelFormat::RGBA32F});
  vk::Image image_destination(context, {"roofline image destination", side, side, PixelFormat::RGBA32F});
  const uint32_t invocations = peak_invocations(context);
  vk::Buffer seeds(context, {"roofline seeds", uint64_t(invocations) * sizeof(float)});
  vk::Buffer sums(context, {"roofline sums", uint64_t(invocations) * sizeof(float)});

  const passes::BufferCopyPass buffer_copy(context);
  const passes::CopyPass image_copy(context);
  const passes::FmaPeakPass fma_peak(context);
  vk::FrameGraph graph(context, "roofline");
  graph.add_pass({.name = "roofline_buffer_transfer",
                  .uses = {{&source, vk::access::transfer_read}, {&transfer_destination, vk::access::transfer_write}},
                  .record = [&](VkCommandBuffer commands) {
                    const VkBufferCopy region{0, 0, roofline.bytes};
                    vkCmdCopyBuffer(commands, source.buffer(), transfer_destination.buffer(), 1, &region);
                  }});
  buffer_copy.add_to(graph, source, destination, roofline.bytes, "roofline_buffer_kernel");
  image_copy.add_to(graph, image_source, image_destination, "roofline_image_kernel");
  fma_peak.add_to(graph, seeds, sums, invocations, kPeakIterations, "roofline_fma_peak");
  for (uint32_t i = 0; i <= frames; ++i) {
    if (i == 1) graph.reset_timings();  // the first run compiles and touches fresh memory
    graph.run();
  }
  for (const vk::PassTiming& timing : graph.timings()) {
    if (timing.name == "roofline_buffer_transfer") roofline.buffer_transfer_gbps = timing.gigabytes_per_second();
    if (timing.name == "roofline_buffer_kernel") roofline.buffer_kernel_gbps = timing.gigabytes_per_second();
    if (timing.name == "roofline_image_kernel") roofline.image_kernel_gbps = timing.gigabytes_per_second();
    if (timing.name == "roofline_fma_peak" && timing.median_ms > 0)
      roofline.peak_gflops = passes::fma_peak_flops(invocations, kPeakIterations) / (timing.median_ms * 1e-3) / 1e9;
  }
  roofline.host_memcpy_gbps = host_memcpy_gbps(roofline.bytes, frames);
  return roofline;
}

}  // namespace rt::pipeline

namespace rt::pipeline {

namespace {

// GFLOP/s of `timing` when `flops` counts its pass, else 0.
double gflops_of(const vk::PassTiming& timing, const PassFlops& flops) {
  const auto counted = flops.find(timing.name);
  return counted != flops.end() && timing.median_ms > 0 ? counted->second / (timing.median_ms * 1e-3) / 1e9 : 0.0;
}

}  // namespace

std::string format_profile(const std::vector<vk::PassTiming>& timings, const Roofline& roofline,
                           const PassFlops& flops) {
  std::string out;
  char line[200];
  std::snprintf(line, sizeof line, "%-22s %10s %8s %12s %10s %10s%s\n", "pass", "median ms", "frames", "MB moved", "GB/s",
                "% roofline", flops.empty() ? "" : "    GFLOP/s     % peak");
  out += line;
  double total = 0.0;
  for (const vk::PassTiming& timing : timings) {
    const double gbps = timing.gigabytes_per_second();
    std::snprintf(line, sizeof line, "%-22s %10.3f %8zu %12.2f %10.2f %10.1f", timing.name.c_str(), timing.median_ms,
                  timing.frames, double(timing.bytes_moved) / 1e6, gbps, 100.0 * roofline.fraction(gbps));
    out += line;
    if (flops.count(timing.name)) {
      const double gflops = gflops_of(timing, flops);
      std::snprintf(line, sizeof line, " %10.2f %10.1f", gflops,
                    roofline.peak_gflops > 0 ? 100.0 * gflops / roofline.peak_gflops : 0.0);
      out += line;
    }
    out += "\n";
    total += timing.median_ms;
  }
  std::snprintf(line, sizeof line, "%-22s %10.3f\n", "sum of medians", total);
  out += line;
  return out;
}

nlohmann::json timings_against_roofline(const std::vector<vk::PassTiming>& timings, const Roofline& roofline,
                                        const PassFlops& flops) {
  nlohmann::json passes = nlohmann::json::object();
  for (const vk::PassTiming& timing : timings) {
    nlohmann::json& pass = passes[timing.name];
    pass = {{"gpu_ms", timing.median_ms},
            {"mb_moved", double(timing.bytes_moved) / 1e6},
            {"gbps", timing.gigabytes_per_second()},
            {"roofline_fraction", roofline.fraction(timing.gigabytes_per_second())}};
    if (const auto counted = flops.find(timing.name); counted != flops.end()) {
      const double gflops = gflops_of(timing, flops);
      pass["gflop_per_frame"] = counted->second / 1e9;
      pass["gflops"] = gflops;
      pass["peak_fraction"] = roofline.peak_gflops > 0 ? gflops / roofline.peak_gflops : 0.0;
    }
  }
  return passes;
}

}  // namespace rt::pipeline
