// `remotetouch bench simulate`: one frame of all six cameras of the default site at full
// resolution (color 1280x720, depth 512x512) with the clap scene's user: GPU ms per pass from
// the frame graph's timestamps, and the wall time of a whole frame (mesh, upload, render).
#include "pipeline/jobs.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include "pipeline/gpu_session.h"
#include "pipeline/site_simulator.h"
#include "sim/motion.h"
#include "sim/person_mesh.h"

namespace rt::pipeline {


int run_bench_simulate(const RunOptions& options) {
  GpuSession session(options);
  sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  scene.resolution_scale = 1.0;
  const sim::SiteSetup& setup = scene.at(Site::A);
  std::vector<RgbdCameraSpec> specs;
  for (const auto& camera : setup.site.cameras) specs.push_back(camera_spec(camera, {}, 1.0));
  RgbdRenderer renderer(session.context(), specs);
  const sim::MotionTrack motion(setup.motion, setup.site.seat, setup.user);

  std::vector<double> wall_ms;
  size_t vertices = 0;
  for (uint32_t frame = 0; frame < options.frames + 2; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    const auto mesh = sim::person_mesh(motion.pose_at(frame / scene.fps), setup.user, scene.mesh_detail);
    renderer.render(mesh, frame);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    vertices = mesh.size();
    if (frame == 1) renderer.graph().reset_timings();  // the first two frames compile pipelines
    if (frame >= 2) wall_ms.push_back(ms);
  }
  std::sort(wall_ms.begin(), wall_ms.end());
  const double median_wall = wall_ms[wall_ms.size() / 2];
  const auto timings = renderer.graph().timings();
  double gpu_total = 0;
  for (const auto& timing : timings) gpu_total += timing.median_ms;
  std::printf("simulate: one frame of %zu cameras (color %ux%u, depth %ux%u), %zu triangles, on %s, median of %u frames\n",
              specs.size(), specs[0].color.intrinsics.width, specs[0].color.intrinsics.height,
              specs[0].depth.intrinsics.width, specs[0].depth.intrinsics.height, vertices / 3,
              session.context().device_name().c_str(), options.frames);
  std::printf("  wall time per frame (mesh + upload + render): %.1f ms; GPU sum of passes: %.1f ms\n", median_wall,
              gpu_total);
  std::printf("%s", vk::format_profile(timings).c_str());
  nlohmann::json report = {{"device", session.context().device_name()},
                           {"frames", options.frames},
                           {"wall_ms_per_frame", median_wall},
                           {"gpu_ms_sum", gpu_total}};
  for (const auto& timing : timings) report["gpu_ms_median"][timing.name] = timing.median_ms;
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_simulate.json") << report.dump(2) << "\n";
  return 0;
}

}  // namespace rt::pipeline
