// `remotetouch compose`: the receiver's compositing passes alone (paper Eq. 4 and 5, then the
// background) on generated layers, with the hand approaching and retracting: a small, fully
// deterministic frame graph for pass dumps and RenderDoc captures. The two-site demo is
// two_site_demo.cpp.
#include "pipeline/jobs.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include "pipeline/receiver_compositor.h"
#include "pipeline/gpu_session.h"
#include "image/image_io.h"

namespace rt::pipeline {
int run_compose(const RunOptions& options) {
  GpuSession session(options);
  vk::Context& context = session.context();
  const uint32_t width = options.width, height = options.height;

  ReceiverCompositor chain(context, width, height, /*keep_layers=*/true);  // each equation's layer, to look at
  vk::FrameGraph graph(context, "compose frame");
  float hand_distance_m = 0.0f;
  chain.add_to(graph, [&] { return hand_distance_m; });

  std::filesystem::create_directories(options.out);
  for (uint32_t frame = 0; frame < options.frames; ++frame) {
    hand_distance_m = demo_hand_distance_m(frame, options.frames);
    session.run_frame(graph, frame);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u.png", frame);
    write_image(options.out / name, vk::download(context, chain.display));
  }
  if (options.dump_passes) dump_pass_outputs(context, graph, options.out / "passes");

  nlohmann::json metrics;
  metrics["device"] = context.device_name();
  metrics["frames"] = options.frames;
  metrics["width"] = width;
  metrics["height"] = height;
  for (const auto& timing : graph.timings()) metrics["gpu_ms_median"][timing.name] = timing.median_ms;
  std::ofstream(options.out / "metrics.json") << metrics.dump(2) << "\n";

  std::cout << "compose: " << options.frames << " frames of " << width << "x" << height << " on " << context.device_name()
            << " written to " << options.out.string() << "/frame_*.png\n";
  if (options.profile) std::cout << vk::format_profile(graph.timings());
  session.report_capture();
  if (context.validation_enabled() && context.validation_errors() > 0) {
    std::cerr << "compose: " << context.validation_errors() << " validation errors\n";
    return 1;
  }
  return 0;
}

}  // namespace rt::pipeline
