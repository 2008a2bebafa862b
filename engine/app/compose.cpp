// `remotetouch compose`: the receiver's compositing passes alone (paper Eq. 4 and 5, then the
// background) on generated layers, with the hand approaching and retracting: a small, fully
// deterministic frame graph for pass dumps and RenderDoc captures. The two-site demo is
// two_site_demo.cpp.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "pipeline/receiver_compositor.h"
#include "pipeline/gpu_session.h"
#include "app/command.h"
#include "app/option_groups.h"
#include "image/image_io.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

int run_compose(const RunOptions& options) {
  GpuSession session(options);
  vk::Context& context = session.context();
  const uint32_t width = options.width, height = options.height;

  ReceiverCompositor chain(context, width, height);
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

class ComposeCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command =
        parent.add_subcommand("compose", "The compositing passes alone on generated layers (pass dumps, RenderDoc captures)");
    add_run_options(*command, options_, "out/compose");
    add_frames_option(*command, options_, 30);
    add_inspection_options(*command, options_);
    options_.width = 640;
    options_.height = 360;
    add_size_options(*command, options_, "Frame", 1, 16384);
    command->add_flag("--dump-passes", options_.dump_passes, "Write every pass output of the last frame (EXR and PNG) to OUT/passes/");
    return command;
  }
  void check() override { check_capture_frame(options_); }
  int run() override { return run_compose(options_); }

 private:
  RunOptions options_;
};

}  // namespace

std::unique_ptr<Command> make_compose_command() { return std::make_unique<ComposeCommand>(); }

}  // namespace rt::app
