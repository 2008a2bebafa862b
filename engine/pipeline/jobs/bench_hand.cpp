// `remotetouch bench hand`: GPU ms of the geometry hand's passes (skinning, rasterization, and
// the appearance adaption graph) at 720p and 1440p, from the frame graphs' timestamps, each as a
// fraction of the roofline measured in the same run (pipeline/roofline.h).
#include "pipeline/jobs.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include "config/assets.h"
#include "pipeline/gpu_session.h"
#include "pipeline/hand_renderer.h"
#include "pipeline/roofline.h"
#include "geometry/target_view.h"
#include "sim/hand_model.h"

namespace rt::pipeline {

namespace {

constexpr uint32_t kHandWarmUpFrames = 2;

nlohmann::json print_timings(const std::string& title, const std::vector<vk::PassTiming>& timings, const Roofline& roofline) {
  std::printf("%s\n%s", title.c_str(), format_profile(timings, roofline).c_str());
  return timings_against_roofline(timings, roofline);
}

nlohmann::json bench_hand_at(GpuSession& session, const Roofline& roofline, uint32_t width, uint32_t height, uint32_t frames) {
  vk::Context& context = session.context();
  const Camera camera = target_view_camera(Eigen::Vector3d(0.0, 0.05, -0.7), Screen{}, width, height);
  HandRenderer renderer(context, config::assets_dir() / "hand", width, height);
  vk::FrameGraph graph(context, "bench hand " + std::to_string(width) + "x" + std::to_string(height));
  renderer.add_to(graph);

  // A right hand 45 cm from the screen, slightly curled, facing the viewer; the portrait for the
  // appearance graph is the hand render itself (its cost does not depend on the colors).
  sim::HandPlacement placement;
  placement.palm = Eigen::Vector3d(0.04, 0.0, 0.45);
  Eigen::Matrix3d facing;
  facing << -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ();
  placement.orientation = Eigen::Quaterniond(facing);
  placement.curl = 0.3;
  HandSkeleton hand = sim::build_hand(placement, false, 1.0);
  hand.elbow = hand.wrist - 0.25 * hand.direction;
  renderer.set_pose(hand, camera);
  vk::Image portrait_color(context, {"bench portrait color", width, height, PixelFormat::RGBA32F});
  vk::Image portrait_depth(context, {"bench portrait depth", width, height, PixelFormat::R32F});

  for (uint32_t frame = 0; frame < kHandWarmUpFrames; ++frame) graph.run();
  graph.reset_timings();
  for (uint32_t frame = 0; frame < frames; ++frame) {
    session.run_frame(graph, frame);
    renderer.adapt_appearance_from(portrait_color, portrait_depth);
  }
  nlohmann::json result{{"width", width}, {"height", height}, {"frames", frames}};
  std::printf("\nhand at %ux%u on %s, median of %u frames\n", width, height, context.device_name().c_str(), frames);
  result["passes"] = print_timings("per frame:", graph.timings(), roofline);
  if (renderer.appearance_graph())
    result["appearance_passes"] = print_timings("appearance adaption (while the hand is beyond d_max):",
                                                renderer.appearance_graph()->timings(), roofline);
  return result;
}

}  // namespace

int run_bench_hand(const RunOptions& options) {
  GpuSession session(options);
  std::vector<std::pair<uint32_t, uint32_t>> sizes = {{1280, 720}, {2560, 1440}};
  if (options.width > 0) sizes = {{options.width, options.height}};
  const Roofline roofline = measure_roofline(session.context());
  std::printf("%s", roofline.describe().c_str());
  nlohmann::json report;
  report["device"] = session.context().device_name();
  report["timing"] = "GPU timestamps around each pass; bytes moved = sizes of the resources read plus written";
  report["roofline"] = roofline.to_json();
  for (const auto& [width, height] : sizes)
    report["runs"].push_back(bench_hand_at(session, roofline, width, height, options.frames));
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_hand.json") << report.dump(2) << "\n";
  std::cout << "\nwritten to " << (options.out / "bench_hand.json").string() << "\n";
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
