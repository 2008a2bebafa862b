// `remotetouch bench compositing`: per-pass GPU time of the compositing passes at 720p and
// 1440p, with the bandwidth each achieves next to a plain copy measured in the same run.
#include "pipeline/jobs.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>
#include <vector>
#include "pipeline/receiver_compositor.h"
#include "pipeline/gpu_session.h"
#include "passes/copy.h"

namespace rt::pipeline {

namespace {

constexpr uint32_t kWarmUpFrames = 2;

nlohmann::json bench_compositing_at(GpuSession& session, uint32_t width, uint32_t height, uint32_t frames) {
  vk::Context& context = session.context();
  ReceiverCompositor chain(context, width, height);
  vk::Image copied(context, {"copied portrait", width, height, PixelFormat::RGBA32F});
  const passes::CopyPass copy_pass(context);
  vk::FrameGraph graph(context, "bench compositing " + std::to_string(width) + "x" + std::to_string(height));
  chain.add_to(graph, [] { return 0.3f; });  // inside the ramp: every hand pixel blends
  copy_pass.add_to(graph, chain.portrait, copied);

  for (uint32_t frame = 0; frame < kWarmUpFrames; ++frame) graph.run();  // JIT, first touch of memory
  graph.reset_timings();
  for (uint32_t frame = 0; frame < frames; ++frame) session.run_frame(graph, frame);

  const std::vector<vk::PassTiming> timings = graph.timings();
  double copy_rate = 0.0;
  for (const auto& timing : timings)
    if (timing.name == "copy") copy_rate = timing.gigabytes_per_second();

  std::printf("\ncompositing at %ux%u on %s, median of %u frames\n", width, height, context.device_name().c_str(), frames);
  std::printf("%-12s %10s %10s %10s %12s\n", "pass", "GPU ms", "MB moved", "GB/s", "of copy GB/s");
  nlohmann::json result;
  result["width"] = width;
  result["height"] = height;
  result["frames"] = frames;
  for (const auto& timing : timings) {
    const double rate = timing.gigabytes_per_second();
    const double fraction = copy_rate > 0 ? rate / copy_rate : 0.0;
    std::printf("%-12s %10.3f %10.2f %10.2f %11.0f%%\n", timing.name.c_str(), timing.median_ms,
                double(timing.bytes_moved) / 1e6, rate, 100.0 * fraction);
    result["passes"][timing.name] = {{"gpu_ms_median", timing.median_ms},
                                     {"bytes_moved", timing.bytes_moved},
                                     {"gb_per_s", rate},
                                     {"fraction_of_copy", fraction}};
  }
  return result;
}

}  // namespace

int run_bench_compositing(const RunOptions& options) {
  GpuSession session(options);
  std::vector<std::pair<uint32_t, uint32_t>> sizes = {{1280, 720}, {2560, 1440}};
  if (options.width > 0) sizes = {{options.width, options.height}};

  nlohmann::json report;
  report["device"] = session.context().device_name();
  report["timing"] = "GPU timestamps around each pass; bytes moved = sizes of the images read plus written";
  for (const auto& [width, height] : sizes)
    report["runs"].push_back(bench_compositing_at(session, width, height, options.frames));
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_compositing.json") << report.dump(2) << "\n";
  std::cout << "\nwritten to " << (options.out / "bench_compositing.json").string() << "\n";
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
