#pragma once
// What the commands that render run on the device, one file each under pipeline/jobs/: the
// receiver's compositing on generated layers, the benchmarks, the simulator's recording and the
// evaluations against its ground truth. The command line (engine/app/) only parses their options.
#include <optional>
#include <string>
#include <vector>

#include "geometry/site_frames.h"
#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"
#include "pipeline/run_options.h"
#include "sim/scene.h"

namespace rt::pipeline {

struct EvalIbrOptions {
  std::string scene = "wave";
  std::string fusion = "min";  // min, avg, or both (each frame rendered with both, compared)
  std::string site = "A";      // whose user is rendered, for the other site's eye
  std::vector<std::string> cameras;  // a fixed selection by name; empty = opposite the touching hand
  // The image-based model (--views, --carve, --refine, ...); its fusion is set from `fusion`.
  IbrSettings ibr;
  nlohmann::json quality;      // what --quality or --budget-ms chose; null: neither
  uint32_t supersample = 3;    // the simulator's color supersampling (scene's own is overridden)
  double resolution_scale = 0; // of the cameras' resolutions; 0 = the scene's own
  bool frames_given = false;   // else the scene's own frame count
  uint32_t first_frame = 0;    // of the scene: where the run starts
  uint32_t frame_step = 1;     // every Nth frame from there: a whole scene's motion at 1/N of the time
  // A recording of the same scene and site whose images replace the simulator's (the JPEG of a
  // k4a recording then is the only difference); empty = the simulator's.
  std::filesystem::path cameras_from;
};

struct SimulateOptions {
  std::string scene = "clap";  // a name under assets/scenes/, or a path to a scene file
  Site site = Site::A;
  bool frames_given = false;   // --frames overrides the scene's frame count
  uint32_t gt_width = 640, gt_height = 360;  // the ground-truth target view
  double resolution_scale = 0.0;             // of the cameras; 0 = the scene's own
  // "recording" (engine/sim/recording.h) or "k4a": one k4a recording per camera
  // (devices/camera/k4a_site_writer.h), the site, tracker and ground truth beside them.
  std::string format = "recording";
  int jpeg_quality = 90;                     // k4a colour (MJPG)
  uint32_t supersample = 0;                  // colour samples per pixel, N x N; 0 = the scene's own
};

struct EvalDualOptions {
  std::string scene = "clap";
  std::vector<std::string> users = {"A", "B"};  // whose hand is measured, as the other site sees it
  // image, geometry, dual, dual_no_appearance, dual_no_shape, hard_switch; empty = all.
  std::vector<std::string> variants;
  IbrSettings ibr;                 // the sender's image-based model (the site's defaults)
  nlohmann::json quality;          // what --quality or --budget-ms chose; null: neither
  HandRendererOptions hand;        // the receiver's geometry hand (the site's defaults)
  bool frames_given = false;       // else the scene's own frame count
  uint32_t first_frame = 0;
  uint32_t frame_step = 1;
  double resolution_scale = 0;     // of the cameras; 0 = the scene's own
  bool plots = true;               // hand_psnr.png and the contact sheets (python3-matplotlib)
  // The remote skeletons reach the receiver this long after their capture; > 0 adds the variant
  // dual_predicted, the hand carried forward to the display time (tracking/skeleton_prediction.h).
  double tracker_latency_ms = 0;
};

struct BenchAccuracyOptions {
  std::vector<std::string> scenes = {"wave", "clap", "approach"};
  std::string grid = "small";  // accuracy_grid.h: tiny, small, full
  uint32_t frame_step = 5;     // every Nth frame of each scene's motion
  bool frames_given = false;   // RunOptions::frames per scene, else each scene's whole motion
  uint32_t supersample = 3;    // the simulated color and truth, as eval ibr's --supersample
  bool plot = true;            // pareto.png (python3-matplotlib)
};

// Which of a scene's frames an evaluation renders: from `first_frame` every `frame_step`-th,
// `frames` of them when given, else to the scene's end; shortens scene.frame_count to the last one
// and returns how many. Throws std::invalid_argument naming `command` for a step of 0 or a first
// frame past the scene's end.
struct FrameSelection {
  uint32_t first_frame = 0, frame_step = 1;
  std::optional<uint32_t> frames;
};
uint32_t select_scene_frames(sim::Scene& scene, const FrameSelection& selection, const std::string& command);

// Each returns the process exit code; errors are thrown.
int run_compose(const RunOptions& options);
int run_bench_compositing(const RunOptions& options);
int run_bench_hand(const RunOptions& options);
// `views_given`: run `base.views` alone, else 2, 4 and 6 views.
int run_bench_ibr(const RunOptions& options, const IbrSettings& base, bool views_given);
// Lumi-Net's kernels (GPU ms) against OpenCV DNN running `onnx` on the same tensors, and the
// lumigraph blending's GPU ms, at options.width x options.height.
int run_bench_lumi(const RunOptions& options, const IbrSettings& base, const std::filesystem::path& onnx);
int run_bench_simulate(const RunOptions& options);
int run_simulate(const RunOptions& options, const SimulateOptions& simulate);
int run_eval_ibr(const RunOptions& options, const EvalIbrOptions& eval);
int run_eval_hand(const RunOptions& options);
int run_eval_dual(const RunOptions& options, const EvalDualOptions& eval);
// Exit code 1 when a configuration's outputs were not finite (the others are still measured).
int run_bench_accuracy(const RunOptions& options, const BenchAccuracyOptions& bench);

}  // namespace rt::pipeline
