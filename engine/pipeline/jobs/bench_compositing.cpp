// `remotetouch bench compositing`: per-pass GPU time of the receiver's compositing at 720p and
// 1440p, with the bandwidth each achieves as a fraction of the roofline measured in the same run
// (pipeline/roofline.h): the one pass a site runs, and the three passes that keep the layers,
// on the same layers.
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
#include "pipeline/roofline.h"

namespace rt::pipeline {

namespace {

constexpr uint32_t kWarmUpFrames = 2;

nlohmann::json bench_compositing_at(GpuSession& session, const Roofline& roofline, uint32_t width, uint32_t height,
                                    uint32_t frames, bool keep_layers) {
  vk::Context& context = session.context();
  ReceiverCompositor chain(context, width, height, keep_layers);
  vk::FrameGraph graph(context, "bench compositing " + std::to_string(width) + "x" + std::to_string(height) +
                                    (keep_layers ? ", layers kept" : ""));
  chain.add_to(graph, [] { return 0.3f; });  // inside the ramp: every hand pixel blends

  for (uint32_t frame = 0; frame < kWarmUpFrames; ++frame) graph.run();  // JIT, first touch of memory
  graph.reset_timings();
  for (uint32_t frame = 0; frame < frames; ++frame) session.run_frame(graph, frame);

  const std::vector<vk::PassTiming> timings = graph.timings();
  double total_ms = 0.0;
  for (const auto& timing : timings) total_ms += timing.median_ms;
  std::printf("\ncompositing at %ux%u%s on %s, median of %u frames: %.3f GPU ms in all\n%s", width, height,
              keep_layers ? " keeping the layers (hand_alpha, overlay, composite)" : " in one pass",
              context.device_name().c_str(), frames, total_ms, format_profile(timings, roofline).c_str());
  return {{"width", width},          {"height", height},         {"frames", frames},
          {"keep_layers", keep_layers}, {"gpu_ms_total", total_ms}, {"passes", timings_against_roofline(timings, roofline)}};
}

}  // namespace

int run_bench_compositing(const RunOptions& options) {
  GpuSession session(options);
  std::vector<std::pair<uint32_t, uint32_t>> sizes = {{1280, 720}, {2560, 1440}};
  if (options.width > 0) sizes = {{options.width, options.height}};

  const Roofline roofline = measure_roofline(session.context());
  std::printf("%s", roofline.describe().c_str());
  nlohmann::json report;
  report["device"] = session.context().device_name();
  report["timing"] = "GPU timestamps around each pass; bytes moved = sizes of the images read plus written";
  report["roofline"] = roofline.to_json();
  for (const auto& [width, height] : sizes) {
    const nlohmann::json one = bench_compositing_at(session, roofline, width, height, options.frames, false);
    const nlohmann::json three = bench_compositing_at(session, roofline, width, height, options.frames, true);
    const double one_ms = one["gpu_ms_total"], three_ms = three["gpu_ms_total"];
    std::printf("one pass %.3f ms, the three passes %.3f ms: one pass %.2fx their speed\n", one_ms, three_ms,
                one_ms > 0 ? three_ms / one_ms : 0.0);
    report["runs"].push_back(one);
    report["runs"].push_back(three);
  }
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_compositing.json") << report.dump(2) << "\n";
  std::cout << "\nwritten to " << (options.out / "bench_compositing.json").string() << "\n";
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
