// `remotetouch bench ibr`: per-pass GPU ms of the image-based model for 2, 4 and 6 views (or
// --views N alone; the other image-based-model options apply to every run) at
// 640x360, 1280x720 and 2560x1440, from the frame graph's timestamps, each pass as a fraction of
// the roofline measured in the same run (pipeline/roofline.h). The
// input is one frame of the clap scene rendered by the simulator at the site's full resolution.
#include "pipeline/jobs.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include "pipeline/gpu_session.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/site_simulator.h"
#include "geometry/target_view.h"
#include "ibr/camera_selection.h"
#include "pipeline/roofline.h"

namespace rt::pipeline {

namespace {

constexpr uint32_t kWarmUpFrames = 2;

}  // namespace

int run_bench_ibr(const RunOptions& options, const IbrSettings& base, bool views_given) {
  GpuSession session(options);
  vk::Context& context = session.context();
  sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  scene.resolution_scale = 1.0;
  scene.frame_count = 1;
  SiteSimulator simulator(context, scene, Site::A);
  const sim::RgbdFrame frame = *simulator.next_frame();
  std::vector<passes::IbrCameraModel> cameras;
  std::vector<Eigen::Vector3d> positions;
  for (size_t k = 0; k < simulator.renderer().camera_count(); ++k) {
    cameras.push_back({simulator.renderer().camera(k).color, simulator.renderer().camera(k).depth});
    positions.push_back(cameras.back().color.position_in_site());
  }
  const Eigen::Vector3d eye = map_point(Site::B, Site::A, scene.at(Site::B).site.seat.head_centre_m);

  std::vector<std::pair<uint32_t, uint32_t>> sizes = {{640, 360}, {1280, 720}, {2560, 1440}};
  if (options.width > 0) sizes = {{options.width, options.height}};
  nlohmann::json report = {{"device", context.device_name()},
                           {"frames", options.frames},
                           {"input", "clap scene, one frame, color " +
                                         std::to_string(cameras[0].color.intrinsics.width) + "x" +
                                         std::to_string(cameras[0].color.intrinsics.height) + ", depth " +
                                         std::to_string(cameras[0].depth.intrinsics.width) + "x" +
                                         std::to_string(cameras[0].depth.intrinsics.height)}};
  report["ibr"] = ibr_settings_json(base);  // views: each run's own
  const Roofline roofline = measure_roofline(context);
  report["roofline"] = roofline.to_json();
  std::printf("%s", roofline.describe().c_str());
  std::printf("bench ibr on %s: %s; median GPU ms of %u frames per pass\n", context.device_name().c_str(),
              report["input"].get<std::string>().c_str(), options.frames);
  for (const auto& [width, height] : sizes)
    for (uint32_t views : views_given ? std::vector<uint32_t>{base.views} : std::vector<uint32_t>{2, 4, 6}) {
      IbrSettings settings = base;
      settings.width = width;
      settings.height = height;
      settings.views = views;
      IbrRenderer renderer(context, cameras, settings);
      const Camera target = target_view_camera(eye, scene.at(Site::A).site.screen, width, height);
      const auto selection = ibr::select_cameras(positions, ibr::TouchingHand::Right, views);
      renderer.prepare(frame.cameras, selection, target);
      std::vector<double> wall_ms;
      for (uint32_t i = 0; i < kWarmUpFrames + options.frames; ++i) {
        if (i == kWarmUpFrames) renderer.graph().reset_timings();
        const auto start = std::chrono::steady_clock::now();
        session.run_frame(renderer.graph(), i);
        if (i >= kWarmUpFrames)
          wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      }
      std::sort(wall_ms.begin(), wall_ms.end());
      const auto timings = renderer.graph().timings();
      double ibr_ms = 0;
      nlohmann::json run = {{"width", width}, {"height", height}, {"views", views}};
      for (const auto& timing : timings) {
        run["gpu_ms"][timing.name] = timing.median_ms;
        ibr_ms += timing.median_ms;
      }
      run["passes"] = timings_against_roofline(timings, roofline);
      run["gpu_ms_image_based_model"] = ibr_ms;
      run["wall_ms_per_frame"] = wall_ms[wall_ms.size() / 2];
      std::printf("\n%ux%u, %u views: image-based model %.2f GPU ms, frame wall %.1f ms\n%s", width, height, views, ibr_ms,
                  run["wall_ms_per_frame"].get<double>(), format_profile(timings, roofline).c_str());
      report["runs"].push_back(run);
    }
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_ibr.json") << report.dump(2) << "\n";
  std::printf("\nwritten to %s\n", (options.out / "bench_ibr.json").string().c_str());
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
