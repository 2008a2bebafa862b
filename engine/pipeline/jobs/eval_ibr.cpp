// `remotetouch eval ibr`: renders a scene's frames with the image-based model from the
// simulated RGBD cameras, for the remote viewer's eye, and measures the portraits against the
// simulator's ground truth of the same target view (engine/ibr/portrait_metrics.h).
#include "pipeline/jobs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include "camera/recorded_site.h"
#include "pipeline/gpu_session.h"
#include "pipeline/ibr_evaluation.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/recorded_depth_registration.h"
#include "pipeline/site_simulator.h"
#include "ibr/camera_selection.h"
#include "ibr/portrait_metrics.h"
#include "image/image_io.h"

namespace rt::pipeline {

namespace {

struct FusionRun {
  std::string name;
  std::unique_ptr<IbrRenderer> renderer;
  IbrEvaluation evaluation;
};

// The recording must be of this site: its cameras by name and in order. Their sizes may differ
// from the scene's: the image-based model takes the recorded ones.
void check_recording_matches(const sim::RecordedRgbdSource& recorded, const sim::SiteDescription& site,
                             const std::filesystem::path& dir) {
  const std::string where = "--cameras-from '" + dir.string() + "'";
  if (recorded.site().cameras.size() != site.cameras.size())
    throw std::invalid_argument(where + " has " + std::to_string(recorded.site().cameras.size()) +
                                " cameras, the scene's site " + std::to_string(site.cameras.size()));
  for (size_t k = 0; k < site.cameras.size(); ++k) {
    if (recorded.site().cameras[k].name != site.cameras[k].name)
      throw std::invalid_argument(where + ": camera " + std::to_string(k) + " is '" + recorded.site().cameras[k].name +
                                  "', the scene's site has '" + site.cameras[k].name + "' (another site?)");
  }
}

// The recorded images of scene frame `index`, in the site's camera order.
std::vector<sim::RgbdImage> recorded_cameras(sim::RecordedRgbdSource& recorded, uint64_t index,
                                             const std::filesystem::path& dir) {
  for (size_t i = 0; i < recorded.frame_count(); ++i)
    if (recorded.frame_index(i) == index) {
      recorded.seek(i);
      return recorded.next_frame()->cameras;
    }
  throw std::invalid_argument("--cameras-from '" + dir.string() + "' has no frame " + std::to_string(index) +
                              " (it holds " + std::to_string(recorded.frame_count()) + ")");
}

HostImage scaled(const HostImage& image, float scale) {
  HostImage out = image;
  for (float& value : out.texels) value *= scale;
  return out;
}

// The portrait over black with its alpha, as a viewer would see it and as PNG keeps it.
HostImage as_png(const HostImage& portrait) {
  HostImage out(portrait.width, portrait.height, PixelFormat::RGBA8);
  out.texels = portrait.texels;
  return out;
}

}  // namespace

int run_eval_ibr(const RunOptions& options, const EvalIbrOptions& eval) {
  sim::Scene scene = sim::load_scene(sim::resolve_scene(eval.scene));
  const uint32_t frames = select_scene_frames(
      scene, {eval.first_frame, eval.frame_step, eval.frames_given ? std::optional(options.frames) : std::nullopt}, "eval ibr");
  scene.color_supersampling = eval.supersample;
  if (eval.resolution_scale > 0) scene.resolution_scale = eval.resolution_scale;
  const Site site = eval.site == "B" ? Site::B : Site::A;
  GpuSession session(options);
  vk::Context& context = session.context();
  SiteSimulator simulator(context, scene, site, options.width, options.height);
  const Camera target = *simulator.renderer().target_view();

  std::vector<std::string> camera_names;
  std::vector<Eigen::Vector3d> positions;
  for (const auto& camera : simulator.site().cameras) {
    camera_names.push_back(camera.name);
    positions.push_back(camera.color_camera().position_in_site());
  }
  // A fixed selection by name (throws naming an unknown camera), else per frame by the hand.
  const std::vector<size_t> fixed_selection =
      eval.cameras.empty() ? std::vector<size_t>{} : ibr::cameras_by_name(camera_names, eval.cameras);
  const uint32_t views = fixed_selection.empty() ? eval.ibr.views : uint32_t(fixed_selection.size());

  // Recorded images stand in for the simulator's, camera by camera, at the intrinsics they were
  // recorded with (a k4a recording's pass through its factory calibration).
  std::unique_ptr<sim::RecordedRgbdSource> recorded;
  std::unique_ptr<RecordedDepthRegistration> registration;
  std::vector<passes::IbrCameraModel> camera_models = simulator.renderer().camera_models();
  if (!eval.cameras_from.empty()) {
    recorded = camera::open_recorded_site(eval.cameras_from);
    check_recording_matches(*recorded, simulator.site(), eval.cameras_from);
    for (size_t k = 0; k < camera_models.size(); ++k) {
      camera_models[k].color.intrinsics = recorded->recorded_intrinsics()[k].color;
      camera_models[k].depth.intrinsics = recorded->recorded_intrinsics()[k].depth;
    }
    registration = std::make_unique<RecordedDepthRegistration>(context, recorded->recorded_intrinsics());
    camera_models = registration->models(camera_models);
  }

  IbrSettings settings = eval.ibr;
  settings.width = options.width;
  settings.height = options.height;
  settings.views = views;
  std::vector<FusionRun> runs;
  for (const std::string& name : {std::string("min"), std::string("avg")}) {
    if (eval.fusion != name && eval.fusion != "both") continue;
    settings.fusion = name == "min" ? passes::DepthFusion::Min : passes::DepthFusion::Average;
    runs.push_back({name, std::make_unique<IbrRenderer>(context, camera_models, settings), {}});
  }

  const std::filesystem::path images_dir = options.out / "images";
  std::filesystem::create_directories(images_dir);
  const uint32_t save_every = std::max(1u, frames / 4);
  const CameraIntrinsics& color = camera_models[0].color.intrinsics;
  const CameraIntrinsics& depth = camera_models[0].depth.intrinsics;
  std::printf("eval ibr: scene %s, site %s's user for the other site's eye, %ux%u (portrait supersampled %ux%u), "
              "%u of %zu cameras (color %ux%u, depth %ux%u), %u frames, simulated color supersampled %ux%u, on %s\n",
              eval.scene.c_str(), eval.site.c_str(), options.width, options.height, settings.supersample,
              settings.supersample, views, positions.size(), color.width, color.height, depth.width,
              depth.height, frames, eval.supersample, eval.supersample, context.device_name().c_str());
  std::printf("blend: %s\n", blending_description(*runs.front().renderer).c_str());
  if (frames == 1 && eval.first_frame > 0) std::printf("scene frame %u\n", eval.first_frame);
  if (frames > 1 && (eval.first_frame > 0 || eval.frame_step > 1))
    std::printf("scene frames %u, %u, ... (every %u)\n", eval.first_frame, eval.first_frame + eval.frame_step, eval.frame_step);
  if (!fixed_selection.empty()) {
    std::string names;
    for (const std::string& name : eval.cameras) names += (names.empty() ? "" : ", ") + name;
    std::printf("cameras fixed: %s\n", names.c_str());
  }
  if (recorded)
    std::printf("cameras' images from %s '%s' (%zu with depth registered into colour)\n",
                camera::recorded_site_kind(eval.cameras_from).c_str(), eval.cameras_from.string().c_str(),
                registration->registered_count());
  std::vector<uint32_t> scene_frames;  // which scene frame each rendered one is
  for (uint32_t index = 0; index < frames; ++index) {
    simulator.seek(eval.first_frame + uint64_t(index) * eval.frame_step);
    std::optional<sim::RgbdFrame> frame = simulator.next_frame();
    if (!frame) break;
    if (recorded) {
      frame->cameras = recorded_cameras(*recorded, frame->index, eval.cameras_from);
      registration->apply(frame->cameras);
    }
    const sim::PersonPose& pose = simulator.last_pose();
    const auto selection = fixed_selection.empty()
                               ? ibr::select_cameras(positions, ibr::touching_hand(pose.right_hand, pose.left_hand), views)
                               : fixed_selection;
    const PortraitTruth truth{simulator.renderer().target_color(), simulator.renderer().target_depth_m(),
                              simulator.renderer().target_part()};
    const bool save = index % save_every == 0 || index + 1 == frames;
    char stem[32];
    scene_frames.push_back(uint32_t(frame->index));
    std::snprintf(stem, sizeof stem, "%04u", uint32_t(frame->index));
    if (save) write_image(images_dir / (std::string(stem) + "_truth.png"), truth.color);
    for (FusionRun& run : runs) {
      const FrameMeasurement measured =
          run.evaluation.measure_frame(session, *run.renderer, index, frame->cameras, selection, target, truth);
      if (!save) continue;
      const std::string prefix = std::string(stem) + "_" + run.name;
      write_image(images_dir / (prefix + "_portrait.png"), as_png(measured.portrait));
      write_image(images_dir / (prefix + "_color_error_x4.png"), scaled(measured.error.color_error, 4.0f));
      write_image(images_dir / (prefix + "_depth_error_per_50mm.png"),
                  scaled(measured.error.depth_error_mm, 1.0f / 50.0f));
    }
    std::fprintf(stderr, "\r  frame %u/%u", index + 1, frames);
  }
  std::fprintf(stderr, "\n");
  if (options.dump_passes)
    for (FusionRun& run : runs) {
      std::filesystem::create_directories(options.out / "passes" / run.name);
      dump_pass_outputs(context, run.renderer->graph(), options.out / "passes" / run.name);
    }

  nlohmann::json report = {{"scene", eval.scene},
                           {"site", eval.site},
                           {"width", options.width},
                           {"height", options.height},
                           {"views", views},
                           {"cameras", fixed_selection.empty() ? nlohmann::json("opposite the touching hand, each frame")
                                                               : nlohmann::json(eval.cameras)},
                           {"refine_hypotheses", settings.refine ? settings.refinement.hypotheses : 0},
                           {"best_views", settings.blend.best_views},
                           {"see_through_carving", settings.carve},
                           {"edge_inset_depth_px", settings.splat.edge_inset},
                           {"color_supersampling", eval.supersample},
                           {"portrait_supersampling", settings.supersample},
                           {"resolution_scale", scene.resolution_scale},
                           {"camera_color", {color.width, color.height}},
                           {"camera_depth", {depth.width, depth.height}},
                           {"average_tolerance_m", settings.splat.average_tolerance_m},
                           {"ibr", ibr_settings_json(settings)},
                           {"quality", eval.quality},
                           {"frames", frames},
                           {"first_frame", eval.first_frame},
                           {"frame_step", eval.frame_step},
                           {"scene_frames", scene_frames},
                           {"device", context.device_name()},
                           {"cameras_from", recorded ? nlohmann::json(eval.cameras_from.string()) : nlohmann::json(nullptr)},
                           {"ground_truth", "the simulator's render of the same target view (no sensor effects), color box-filtered "
                                            "over color_supersampling^2 samples per pixel like the cameras' images"},
                           {"color_error", "RGB in [0, 1], portrait premultiplied by its alpha against the truth"}};
  report["blend"] = blending_name(settings.blending);
  std::printf("\n%-6s %11s %13s %18s %10s %14s %14s\n", "fusion", "psnr_fg_db", "psnr_hand_db", "depth_mae_edge_mm",
              "alpha_iou", "depth_bias_mm", "GPU ms/frame");
  for (FusionRun& run : runs) {
    const nlohmann::json result = run.evaluation.to_json(run.renderer->graph());
    const ibr::PortraitMetrics& metrics = run.evaluation.metrics();
    std::printf("%-6s %11.2f %13.2f %18.2f %10.4f %14.2f %14.2f\n", run.name.c_str(), metrics.psnr_fg_db(),
                metrics.psnr_hand_db(), metrics.depth_mae_edge_mm(), metrics.alpha_iou(), metrics.depth_bias_mm(),
                result["gpu_ms_total"].get<double>());
    report["by_fusion"][run.name] = result;
  }
  std::printf("\nforeground error by region (share of pixels, share of squared error, PSNR dB):\n");
  for (FusionRun& run : runs) {
    std::printf("[%s]", run.name.c_str());
    for (size_t r = 0; r < ibr::kErrorRegionCount; ++r) {
      const auto region = ibr::ErrorRegion(r);
      const ibr::PortraitMetrics& metrics = run.evaluation.metrics();
      std::printf("  %s %.1f%% %.1f%% %.2f", ibr::kErrorRegionNames[r], 100 * metrics.region_pixel_share(region),
                  100 * metrics.region_error_share(region), metrics.region_psnr_db(region));
    }
    std::printf("\n");
  }
  std::printf("\nworst frames (foreground PSNR dB):\n");
  for (FusionRun& run : runs) {
    const std::vector<double>& psnr = run.evaluation.frame_psnr_fg_db();
    std::vector<size_t> order;
    for (size_t f = 0; f < psnr.size(); ++f)
      if (std::isfinite(psnr[f])) order.push_back(f);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return psnr[a] < psnr[b]; });
    std::printf("[%s]", run.name.c_str());
    for (size_t k = 0; k < std::min<size_t>(order.size(), 5); ++k) std::printf("  %04u %.2f", scene_frames[order[k]], psnr[order[k]]);
    std::printf("\n");
  }
  // The first mode's figures at the top level, where scripts look first.
  for (const auto& [key, value] : report["by_fusion"][runs.front().name].items()) report[key] = value;
  report["fusion"] = runs.front().name;
  std::printf("\nper-pass GPU ms (median over frames):\n");
  for (FusionRun& run : runs) std::printf("[%s]\n%s", run.name.c_str(), vk::format_profile(run.renderer->graph().timings()).c_str());
  std::ofstream(options.out / "metrics.json") << report.dump(2) << "\n";
  std::cout << "written to " << (options.out / "metrics.json").string() << " and " << images_dir.string() << "/\n";
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
