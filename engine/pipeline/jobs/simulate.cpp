// `remotetouch simulate --scene NAME --out DIR`: records one site of a synthetic scene in the
// recording format (engine/sim/recording.h): every camera's color and 16-bit depth, the
// tracker's Leap v6 frames, and the ground truth from the remote viewer's eye. With --format k4a
// the cameras are written as k4a recordings instead, one .mkv each, as real cameras record.
#include "pipeline/jobs.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include "camera/k4a_site_writer.h"
#include "config/json.h"
#include "pipeline/gpu_session.h"
#include "pipeline/site_simulator.h"
#include "sim/leap_json.h"
#include "sim/recording.h"
#include "sim/tracker_sim.h"

namespace rt::pipeline {

int run_simulate(const RunOptions& options, const SimulateOptions& simulate) {
  sim::Scene scene = sim::load_scene(sim::resolve_scene(simulate.scene));
  if (simulate.frames_given) scene.frame_count = options.frames;
  if (simulate.resolution_scale > 0) scene.resolution_scale = simulate.resolution_scale;
  if (simulate.supersample > 0) scene.color_supersampling = simulate.supersample;
  const Site site = simulate.site;

  // The calibration describes the images as recorded: the cameras' intrinsics at the resolution
  // scale the simulator renders them at, so that a reader needs no scale of its own.
  sim::SiteDescription recorded = scene.at(site).site;
  for (sim::RgbdCamera& camera : recorded.cameras) {
    camera.color = scaled_intrinsics(camera.color, scene.resolution_scale);
    camera.depth = scaled_intrinsics(camera.depth, scene.resolution_scale);
  }
  // A k4a recording holds only what a device stores, so the site (where the cameras stand)
  // goes beside the recordings, as for a real installation. The cameras' sizes are checked
  // before anything renders.
  std::unique_ptr<sim::RecordingWriter> recording;
  std::unique_ptr<camera::k4a::SiteWriter> k4a;
  if (simulate.format == "k4a") {
    if (scene.fps != std::round(scene.fps))
      throw std::invalid_argument("--format k4a: the scene's " + std::to_string(scene.fps) + " fps is not 5, 15 or 30");
    try {
      k4a = std::make_unique<camera::k4a::SiteWriter>(options.out, recorded, uint32_t(scene.fps), simulate.jpeg_quality);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(e.what()) +
                                  "; the default site's cameras are k4a modes at --resolution-scale 1");
    }
    config::write_json_file(options.out / "site.json", sim::site_to_json(recorded));
  } else {
    recording = std::make_unique<sim::RecordingWriter>(options.out, sim::site_to_json(recorded));
  }
  GpuSession session(options);
  SiteSimulator simulator(session.context(), scene, site, simulate.gt_width, simulate.gt_height);
  std::printf("simulate: scene '%s', site %s, %u frames, %zu cameras -> %s\n", scene.name.c_str(), site_name(site),
              scene.frame_count, scene.at(site).site.cameras.size(), options.out.string().c_str());
  while (true) {
    // The capture of frame N (if asked) brackets that frame's render.
    const bool capture = int(simulator.frames_done()) == options.capture_frame;
    std::optional<sim::RgbdFrame> frame;
    if (capture) {
      session.begin_capture();
      frame = simulator.next_frame();
      session.end_capture();
    } else {
      frame = simulator.next_frame();
    }
    if (!frame) break;
    if (k4a) k4a->write_frame(*frame);
    else recording->write_frame(*frame);
    RgbdRenderer& renderer = simulator.renderer();
    std::vector<HostImage> foregrounds;
    for (size_t k = 0; k < renderer.camera_count(); ++k) foregrounds.push_back(renderer.foreground(k));
    if (renderer.has_target_view())
      sim::write_ground_truth(options.out, frame->index, renderer.target_color(), renderer.target_depth_m(),
                              renderer.target_part(), foregrounds);
    std::printf("\r  frame %llu/%u", static_cast<unsigned long long>(frame->index + 1), scene.frame_count);
    std::fflush(stdout);
  }
  std::printf("\n");
  if (k4a) {
    k4a->close();
    std::printf("  k4a recordings (MJPG quality %d): one .mkv per camera, site.json beside them\n",
                simulate.jpeg_quality);
  }

  // The tracker runs at 50 Hz over the same duration.
  sim::SimulatedHandTracker tracker = sim::make_simulated_tracker(scene, site);
  std::ofstream lines(options.out / "tracker.jsonl");
  size_t tracker_frames = 0;
  while (auto frame = tracker.next_frame()) {
    lines << sim::leap_json_line(*frame) << "\n";
    ++tracker_frames;
  }
  std::printf("  %zu tracker frames in tracker.jsonl\n", tracker_frames);
  if (options.profile) std::cout << vk::format_profile(simulator.renderer().graph().timings());
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
