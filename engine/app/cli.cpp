#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <iostream>

#include "app/calibrate.h"
#include "app/eval_ibr.h"
#include "app/eval_hand.h"
#include "app/options.h"
#include "app/simulate.h"
#include "app/two_site_demo.h"

namespace rt::app {

using namespace rt::site;
namespace {

void add_common_options(CLI::App& command, RunOptions& options, const std::string& default_out) {
  options.out = default_out;
  command.add_option("--out", options.out, "Output directory")->capture_default_str();
  command.add_option("--device", options.device,
                     "Vulkan device: a part of its name (e.g. llvmpipe, NVIDIA); default prefers a GPU");
  command.add_flag("--validation", options.validation, "Enable the Khronos validation layer; errors fail the run");
}

void add_frame_options(CLI::App& command, RunOptions& options, uint32_t default_frames) {
  options.frames = default_frames;
  command.add_option("--frames", options.frames, "Frames to render")->check(CLI::Range(1u, 1000000u))->capture_default_str();
  command.add_flag("--profile", options.profile, "Print per-pass GPU times (median over the frames)");
  command.add_option("--capture-frame", options.capture_frame,
                     "Capture this frame (0-based) with RenderDoc, when RenderDoc is present")
      ->check(CLI::NonNegativeNumber);
}

void check_capture_frame(const RunOptions& options) {
  if (options.capture_frame >= int(options.frames))
    throw CLI::ValidationError("--capture-frame", "frame " + std::to_string(options.capture_frame) +
                                                      " is past the last frame (--frames " +
                                                      std::to_string(options.frames) + " renders 0.." +
                                                      std::to_string(options.frames - 1) + ")");
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{"RemoteTouch: two people clap hands through their screens (Vulkan engine)", "remotetouch"};
  app.require_subcommand(1);

  DemoCommand demo(app);

  RunOptions bench;
  std::string bench_what;
  CLI::App* bench_command = app.add_subcommand("bench", "Print per-pass GPU times and bandwidth against a copy pass");
  bench_command->add_option("what", bench_what,
                            "Which benchmark: compositing (GPU ms per pass), touch (touch-start to motor command; "
                            "--frames claps), simulate (one frame of all six cameras at full resolution), ibr (the image-based "
                            "model's passes for 2, 4, 6 views), hand (skinning and rasterization of the geometry hand), net "
                            "(portraits at 30 fps over loopback: bytes/s on the wire, encode/decode ms; --frames portraits per size)")
      ->required()
      ->check(CLI::IsMember({"compositing", "touch", "simulate", "ibr", "hand", "net"}));
  add_common_options(*bench_command, bench, "out/bench");
  add_frame_options(*bench_command, bench, 20);
  auto* width = bench_command->add_option("--width", bench.width, "Only this width (default: 1280x720 and 2560x1440)")
                    ->check(CLI::Range(1u, 16384u));
  auto* height = bench_command->add_option("--height", bench.height, "Only this height")->check(CLI::Range(1u, 16384u));
  width->needs(height);
  height->needs(width);

  CalibrateCommand calibrate(app);
  SiteCommand site(app);

  RunOptions compose;
  CLI::App* compose_command = app.add_subcommand("compose", "The compositing passes alone on generated layers (pass dumps, RenderDoc captures)");
  add_common_options(*compose_command, compose, "out/compose");
  add_frame_options(*compose_command, compose, 30);
  compose.width = 640;
  compose.height = 360;
  compose_command->add_option("--width", compose.width, "Frame width in pixels")->check(CLI::Range(1u, 16384u))->capture_default_str();
  compose_command->add_option("--height", compose.height, "Frame height in pixels")->check(CLI::Range(1u, 16384u))->capture_default_str();
  compose_command->add_flag("--dump-passes", compose.dump_passes, "Write every pass output of the last frame (EXR and PNG)");


  CLI::App* eval_command = app.add_subcommand("eval", "Measure a part of the system against the simulator's ground truth");
  eval_command->require_subcommand(1);
  EvalHandCommand eval_hand(*eval_command);

  RunOptions simulate;
  SimulateOptions simulate_options;
  std::string simulate_site = "A";
  CLI::App* simulate_command =
      app.add_subcommand("simulate", "Record one site of a synthetic scene: RGBD cameras, tracker, ground truth");
  simulate_command->add_option("--scene", simulate_options.scene, "Scene name under assets/scenes/, or a scene file")
      ->capture_default_str();
  simulate_command->add_option("--site", simulate_site, "Which site to record")->check(CLI::IsMember({"A", "B"}))
      ->capture_default_str();
  add_common_options(*simulate_command, simulate, "out/simulate");
  add_frame_options(*simulate_command, simulate, 1);
  simulate_command->get_option("--frames")->description("Frames to record (default: the scene's own count)");
  simulate_command->add_option("--resolution-scale", simulate_options.resolution_scale,
                               "Camera resolution scale (default: the scene's)")->check(CLI::Range(0.01, 1.0));
  simulate_command->add_option("--gt-width", simulate_options.gt_width, "Ground-truth target view width")
      ->check(CLI::Range(1u, 16384u))->capture_default_str();
  simulate_command->add_option("--gt-height", simulate_options.gt_height, "Ground-truth target view height")
      ->check(CLI::Range(1u, 16384u))->capture_default_str();

  RunOptions eval_ibr;
  EvalIbrOptions eval_ibr_options;
  CLI::App* eval_ibr_command = eval_command->add_subcommand(
      "ibr", "The image-based model (fusion, warping, blending) against ground truth: metrics.json, PNGs, a table");
  eval_ibr_command->add_option("--scene", eval_ibr_options.scene, "Scene name under assets/scenes/, or a scene file")
      ->capture_default_str();
  eval_ibr_command->add_option("--fusion", eval_ibr_options.fusion, "Depth fusion: min (the paper), avg (baseline), both")
      ->check(CLI::IsMember({"min", "avg", "both"}))->capture_default_str();
  CLI::Option* views_option = eval_ibr_command->add_option("--views", eval_ibr_options.views, "Cameras used per frame")
      ->check(CLI::Range(1u, 6u))->capture_default_str();
  eval_ibr_command
      ->add_option("--cameras", eval_ibr_options.cameras,
                   "These cameras (site names, comma-separated) in every frame, instead of the ones opposite the touching hand")
      ->delimiter(',')
      ->excludes(views_option);
  eval_ibr_command->add_flag("--carve", eval_ibr_options.carve,
                             "See-through carving: a fused point that a camera looks straight through takes the surface behind "
                             "(reopens finger gaps narrower than a depth pixel)");
  eval_ibr_command->add_option("--refine", eval_ibr_options.refine_hypotheses,
                               "Plane-sweep refinement with this many depth hypotheses (0 = off)")
      ->check(CLI::Range(0, 64))->capture_default_str();
  eval_ibr_command->add_option("--best-views", eval_ibr_options.best_views,
                               "Blending's k: the k-1 best views blend, the k-th has weight 0 (2 = the best view alone; "
                               "views + 1 = all of them)")
      ->check(CLI::Range(2, RT_IBR_MAX_VIEWS + 1))->capture_default_str();
  eval_ibr_command->add_option("--average-tolerance", eval_ibr_options.average_tolerance_m,
                               "avg fusion: depths up to this many metres behind the nearest agree with it and join the mean (large, e.g. 0.1 = a plain mean that blurs edges)")
      ->check(CLI::Range(0.0f, 10.0f))->capture_default_str();
  eval_ibr_command->add_option("--edge-inset", eval_ibr_options.edge_inset_depth_px,
                               "Splat sides on outlines and depth edges pulled in by this much of a depth pixel "
                               "(0.3 gains with --views 6 and --portrait-supersample 3; loses with four views)")
      ->check(CLI::Range(0.0f, 0.49f))->capture_default_str();
  eval_ibr_command->add_option("--supersample", eval_ibr_options.supersample,
                               "Simulated color and ground truth rendered at N x N samples per pixel, box-filtered (odd)")
      ->check(CLI::IsMember({1u, 3u, 5u, 7u}))->capture_default_str();
  eval_ibr_command->add_option("--portrait-supersample", eval_ibr_options.portrait_supersample,
                               "Portrait rendered at N x N samples per pixel and resolved (partial alpha on edges)")
      ->check(CLI::Range(1u, 4u))->capture_default_str();
  eval_ibr_command->add_option("--resolution-scale", eval_ibr_options.resolution_scale,
                               "Camera resolution scale (default: the scene's; 1 is the site's own)")
      ->check(CLI::Range(0.01, 1.0));
  eval_ibr_command->add_flag("--dump-passes", eval_ibr.dump_passes,
                             "Write every pass output of the last frame (EXR and PNG) to OUT/passes/FUSION/");
  eval_ibr_command->add_option("--first-frame", eval_ibr_options.first_frame, "Scene frame to start at")
      ->check(CLI::Range(0u, 1000000u))->capture_default_str();
  eval_ibr_command->add_option("--frame-step", eval_ibr_options.frame_step,
                               "Render every Nth scene frame (the whole motion at 1/N of the time)")
      ->check(CLI::Range(1u, 1000u))->capture_default_str();
  eval_ibr_command->add_option("--site", eval_ibr_options.site, "Whose user is rendered")
      ->check(CLI::IsMember({"A", "B"}))->capture_default_str();
  add_common_options(*eval_ibr_command, eval_ibr, "out/eval-ibr");
  add_frame_options(*eval_ibr_command, eval_ibr, 1);
  eval_ibr_command->get_option("--frames")->description("Frames to render (default: the scene's own count)");
  eval_ibr.width = 640;
  eval_ibr.height = 360;
  eval_ibr_command->add_option("--width", eval_ibr.width, "Target view width")->check(CLI::Range(1u, 16384u))
      ->capture_default_str();
  eval_ibr_command->add_option("--height", eval_ibr.height, "Target view height")->check(CLI::Range(1u, 16384u))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
    if (compose_command->parsed()) check_capture_frame(compose);
    if (bench_command->parsed()) check_capture_frame(bench);
    if (eval_ibr_command->parsed()) {
      eval_ibr_options.frames_given = eval_ibr_command->count("--frames") > 0;
      if (eval_ibr_options.frames_given) check_capture_frame(eval_ibr);
    }
    if (simulate_command->parsed()) {
      simulate_options.frames_given = simulate_command->count("--frames") > 0;
      simulate_options.site = simulate_site == "B" ? Site::B : Site::A;
      if (simulate_options.frames_given) check_capture_frame(simulate);
    }
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }

  try {
    if (demo.parsed()) return demo.run();
    if (site.parsed()) return site.run();
    if (compose_command->parsed()) return run_compose(compose);
    if (bench_command->parsed()) return run_bench(bench_what, bench);
    if (simulate_command->parsed()) return run_simulate(simulate, simulate_options);
    if (eval_ibr_command->parsed()) return run_eval_ibr(eval_ibr, eval_ibr_options);
    if (calibrate.parsed()) return calibrate.run();
    if (eval_hand.parsed()) return eval_hand.run();
  } catch (const std::exception& error) {
    std::cerr << "remotetouch: error: " << error.what() << "\n";
    return 1;
  }
  return 1;
}

}  // namespace rt::app
