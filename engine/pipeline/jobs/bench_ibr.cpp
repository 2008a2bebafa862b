// `remotetouch bench ibr`: per-pass GPU ms of the image-based model for 2, 4 and 6 views (or
// --views N alone; the other image-based-model options apply to every run) at
// 640x360, 1280x720 and 2560x1440, from the frame graph's timestamps, each pass as a fraction of
// the roofline measured in the same run (pipeline/roofline.h), and next to the same warp and
// lumigraph blend run on the CPU with OpenCV (pipeline/ibr_cpu_peer.h) from the same surface, on
// the same cores: the figure a user would compare the GPU path with. With lumigraph blending the
// other GPU path runs on the same frame too (one pass against warp-then-blend), timed and
// compared. The input is one frame of the clap scene rendered by the simulator at the site's
// full resolution.
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
#include "pipeline/ibr_cpu_peer.h"
#include "pipeline/roofline.h"

namespace rt::pipeline {

namespace {

constexpr uint32_t kIbrWarmUpFrames = 2;

double median_of(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

// The peer's portrait against the GPU's where either covers: how far apart the two computations
// are (the peer samples with OpenCV's fixed-point bilinear weights).
nlohmann::json compare_portraits(const cv::Mat& peer, const HostImage& gpu) {
  double squared = 0;
  size_t covered = 0, alpha_differs = 0;
  for (int y = 0; y < peer.rows; ++y)
    for (int x = 0; x < peer.cols; ++x) {
      const cv::Vec4f p = peer.at<cv::Vec4f>(y, x);
      const float gpu_alpha = gpu.at(uint32_t(x), uint32_t(y), 3);
      if (!(p[3] > 0.5f) && !(gpu_alpha > 0.5f)) continue;
      ++covered;
      if ((p[3] > 0.5f) != (gpu_alpha > 0.5f)) ++alpha_differs;
      for (int c = 0; c < 3; ++c) {
        const double d = double(p[c]) - gpu.at(uint32_t(x), uint32_t(y), uint32_t(c));
        squared += d * d;
      }
    }
  const double mse = covered ? squared / (3.0 * covered) : 0.0;
  return {{"psnr_db", mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0},
          {"alpha_differs_fraction", covered ? double(alpha_differs) / covered : 0.0}};
}

// The GPU's warp and blend: ibr_warp_blend, or ibr_warp + ibr_blend on the split path.
double warp_and_blend_ms(const std::vector<vk::PassTiming>& timings) {
  double ms = 0;
  for (const auto& timing : timings)
    if (timing.name == "ibr_warp_blend" || timing.name == "ibr_warp" || timing.name == "ibr_blend") ms += timing.median_ms;
  return ms;
}

// The warp's and the lumigraph blend's arithmetic on this frame, as the references count it, for
// each GPU pass that does it.
PassFlops warp_and_blend_flops(const passes::WarpWork& work) {
  const double warp = work.flops(), blend = passes::ulr_blend_flops(work.seen, work.covered);
  return {{"ibr_warp", warp}, {"ibr_warp_blend", warp + blend}, {"ibr_blend", blend}};
}

nlohmann::json work_json(const passes::WarpWork& work) {
  return {{"surface_pixels", work.surface_pixels}, {"samples", work.samples}, {"in_front", work.in_front},
          {"inside", work.inside},   {"seen", work.seen},       {"covered_pixels", work.covered}};
}

// Runs `renderer`'s prepared frame `frames` times after a warm-up; the frames' wall ms, sorted.
std::vector<double> run_timed(GpuSession& session, IbrRenderer& renderer, uint32_t frames) {
  std::vector<double> wall_ms;
  for (uint32_t i = 0; i < kIbrWarmUpFrames + frames; ++i) {
    if (i == kIbrWarmUpFrames) renderer.graph().reset_timings();
    const auto start = std::chrono::steady_clock::now();
    session.run_frame(renderer.graph(), i);
    if (i >= kIbrWarmUpFrames)
      wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(wall_ms.begin(), wall_ms.end());
  return wall_ms;
}

// The largest difference of any channel between two portraits of one size.
double max_difference(const HostImage& a, const HostImage& b) {
  double largest = 0;
  for (uint32_t y = 0; y < a.height; ++y)
    for (uint32_t x = 0; x < a.width; ++x)
      for (uint32_t c = 0; c < 4; ++c) largest = std::max(largest, double(std::abs(a.at(x, y, c) - b.at(x, y, c))));
  return largest;
}

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
      const std::vector<double> wall_ms = run_timed(session, renderer, options.frames);
      const auto timings = renderer.graph().timings();
      // The warp's inputs as the GPU had them, for the arithmetic count and the CPU peer.
      const bool split = splits_warp(settings);
      IbrRenderer::WarpInputs warp = renderer.warp_inputs();
      const HostImage fused_depth = vk::download(context, warp.depth), color = vk::download(context, warp.color),
                      points = vk::download(context, warp.points);
      passes::WarpWork work;
      (void)passes::ibr_warp_reference(warp.table, fused_depth, color, points, settings.warp, &work);
      const PassFlops flops = warp_and_blend_flops(work);
      double ibr_ms = 0;
      nlohmann::json run = {{"width", width}, {"height", height}, {"views", views}};
      for (const auto& timing : timings) {
        run["gpu_ms"][timing.name] = timing.median_ms;
        ibr_ms += timing.median_ms;
      }
      run["passes"] = timings_against_roofline(timings, roofline, flops);
      run["warp_work"] = work_json(work);
      run["gpu_ms_image_based_model"] = ibr_ms;
      run["wall_ms_per_frame"] = wall_ms[wall_ms.size() / 2];
      std::printf("\n%ux%u, %u views: image-based model %.2f GPU ms, frame wall %.1f ms\n%s", width, height, views, ibr_ms,
                  run["wall_ms_per_frame"].get<double>(), format_profile(timings, roofline, flops).c_str());
      std::printf("warp's arithmetic (as the reference counts it): %llu of %u pixels with a surface, %llu view samples, "
                  "%llu in front of their camera, %llu inside its images, %llu seen; %.1f MFLOP with the blend\n",
                  (unsigned long long)work.surface_pixels, width * height, (unsigned long long)work.samples,
                  (unsigned long long)work.in_front, (unsigned long long)work.inside, (unsigned long long)work.seen,
                  flops.at("ibr_warp_blend") * 1e-6);

      // The CPU peer from the surface the GPU warped through, timed over as many frames.
      const IbrCpuPeerInputs peer_inputs = cpu_peer_inputs(warp.table, fused_depth, color, points);
      std::vector<double> maps_ms, sample_ms, blend_ms, peer_ms;
      IbrCpuPeerResult peer;
      for (uint32_t i = 0; i < options.frames; ++i) {
        peer = run_ibr_cpu_peer(peer_inputs, settings.warp, settings.blend);
        maps_ms.push_back(peer.times.maps_ms);
        sample_ms.push_back(peer.times.sample_ms);
        blend_ms.push_back(peer.times.blend_ms);
        peer_ms.push_back(peer.times.total());
      }
      const double gpu_warp_blend_ms = warp_and_blend_ms(timings);
      const double peer_total = median_of(peer_ms);
      run["cpu_peer"] = {{"opencv_threads", cv::getNumThreads()},
                         {"ms_maps", median_of(maps_ms)},
                         {"ms_remap", median_of(sample_ms)},
                         {"ms_blend", median_of(blend_ms)},
                         {"ms_total", peer_total},
                         {"gpu_ms_warp_and_blend", gpu_warp_blend_ms},
                         {"peer_over_gpu", gpu_warp_blend_ms > 0 ? peer_total / gpu_warp_blend_ms : 0.0},
                         {"against_gpu_portrait", nullptr}};
      // With supersampling the GPU resolves a finer portrait than the warp's: nothing to compare.
      const HostImage portrait = vk::download(context, renderer.portrait_before_fill());
      if (portrait.width == uint32_t(peer.portrait.cols) && portrait.height == uint32_t(peer.portrait.rows))
        run["cpu_peer"]["against_gpu_portrait"] = compare_portraits(peer.portrait, portrait);
      const nlohmann::json& p = run["cpu_peer"];
      std::printf("CPU peer (OpenCV, %d threads): warp and blend %.2f ms (maps %.2f, remap %.2f, blend %.2f) against the "
                  "GPU's %s %.2f ms: GPU %.2fx the peer's speed",
                  cv::getNumThreads(), peer_total, p["ms_maps"].get<double>(), p["ms_remap"].get<double>(),
                  p["ms_blend"].get<double>(), split ? "ibr_warp + ibr_blend" : "ibr_warp_blend", gpu_warp_blend_ms,
                  p["peer_over_gpu"].get<double>());
      if (p["against_gpu_portrait"].is_null())
        std::printf(" (portraits not compared: the GPU's is supersampled)\n");
      else
        std::printf("; portraits agree to %.1f dB, alpha differs on %.2f %% of the covered pixels\n",
                    p["against_gpu_portrait"]["psnr_db"].get<double>(),
                    100.0 * p["against_gpu_portrait"]["alpha_differs_fraction"].get<double>());

      // Lumigraph blending's other path on the GPU, the same frame: what the one-pass warp and
      // blend saves over writing every view's warp and reading it back.
      if (settings.blending == IbrBlending::Ulr) {
        IbrSettings other = settings;
        other.split_warp = !split;
        IbrRenderer peer_renderer(context, cameras, other);
        peer_renderer.prepare(frame.cameras, selection, target);
        (void)run_timed(session, peer_renderer, options.frames);
        const double other_ms = warp_and_blend_ms(peer_renderer.graph().timings());
        const HostImage other_portrait = vk::download(context, peer_renderer.portrait_before_fill());
        const double fused_ms = split ? other_ms : gpu_warp_blend_ms, split_ms = split ? gpu_warp_blend_ms : other_ms;
        run["split_against_fused"] = {{"gpu_ms_fused", fused_ms},
                                      {"gpu_ms_split", split_ms},
                                      {"split_over_fused", fused_ms > 0 ? split_ms / fused_ms : 0.0},
                                      {"max_difference", max_difference(portrait, other_portrait)}};
        std::printf("GPU warp and blend: one pass (ibr_warp_blend) %.2f ms, split (ibr_warp + ibr_blend) %.2f ms: one "
                    "pass %.2fx the split's speed; portraits differ by at most %.2g\n",
                    fused_ms, split_ms, run["split_against_fused"]["split_over_fused"].get<double>(),
                    run["split_against_fused"]["max_difference"].get<double>());
      }
      report["runs"].push_back(run);
    }
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_ibr.json") << report.dump(2) << "\n";
  std::printf("\nwritten to %s\n", (options.out / "bench_ibr.json").string().c_str());
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
