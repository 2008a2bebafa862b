#include "app/calibrate.h"

#include "calibration/camera_network.h"
#include "calibration/extrinsics_calibration.h"
#include "calibration/screen_trilateration.h"
#include "calibration/synthetic_site.h"
#include "calibration/tracker_calibration.h"

namespace rt::app {
namespace {

// --device is on every subcommand of the CLI; calibration has no use for a GPU.
void add_device_option(CLI::App& command, std::string& device) {
  command.add_option("--device", device, "Not used: calibration runs on the CPU (accepted like on every command)");
}

}  // namespace

CalibrateCommand::CalibrateCommand(CLI::App& app) {
  command_ = app.add_subcommand("calibrate", "Calibrate a site: camera intrinsics, camera poses, the hand tracker");
  command_->require_subcommand(1);

  IntrinsicsCommandOptions& in = intrinsics_options_;
  in.out = "out/calibration/intrinsics.json";
  intrinsics_ = command_->add_subcommand(
      "intrinsics", "One camera's focal lengths, principal point and distortion from chessboard photographs (Zhang)");
  intrinsics_->add_option("--images", in.images, "Photographs: paths or quoted patterns such as 'data/left*.jpg'")
      ->required();
  intrinsics_->add_option("--board", in.board, "Inner corners per row and per column, COLSxROWS (e.g. 9x6)")->required();
  intrinsics_->add_option("--square", in.square_m, "Side of one square in metres (e.g. 0.025)")->required();
  intrinsics_->add_option("--out", in.out, "Camera JSON to write")->capture_default_str();
  add_device_option(*intrinsics_, unused_device_);
  intrinsics_->add_flag("--fix-aspect-ratio", in.fix_aspect_ratio, "Square pixels: estimate one focal length (fx = fy)");
  intrinsics_->add_flag("--rational-model", in.rational_model, "Also estimate k4, k5, k6 (wide-angle lenses)");

  ExtrinsicsCommandOptions& ex = extrinsics_options_;
  ex.max_distance_residual_mm = calibration::kMaxCornerDistanceResidualM * 1000.0;
  ex.max_link_rms_px = calibration::kMaxLinkRmsPx;
  ex.max_alignment_residual_mm = calibration::kMaxAlignmentResidualM * 1000.0;
  extrinsics_ = command_->add_subcommand(
      "extrinsics", "The cameras' poses in the site frame, from simultaneous chessboard views and each camera's "
                    "measured distances to the four screen corners");
  extrinsics_->add_option("--input", ex.input, "Extrinsics input JSON (see engine/calibration/extrinsics_input.h)")
      ->required()
      ->check(CLI::ExistingFile);
  extrinsics_->add_option("--site", ex.site,
                          "Site file to update in place (start from a copy of assets/sites/default.json): "
                          "each calibrated camera's color intrinsics and pose, by name; the rest is kept")
      ->required();
  add_device_option(*extrinsics_, unused_device_);
  extrinsics_->add_option("--max-distance-residual-mm", ex.max_distance_residual_mm,
                          "Largest disagreement between a camera's four corner distances")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  extrinsics_->add_option("--max-link-rms-px", ex.max_link_rms_px,
                          "Largest RMS reprojection error of a camera pair's shared views")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  extrinsics_->add_option("--max-alignment-residual-mm", ex.max_alignment_residual_mm,
                          "Largest distance between a camera's position from the chessboards and from the distances")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();

  TrackerCommandOptions& tr = tracker_options_;
  tr.inlier_threshold_mm = calibration::kDefaultInlierThresholdMm;
  tracker_ = command_->add_subcommand(
      "tracker", "The hand tracker's pose in the site frame from fingertip touches on known screen points");
  tracker_->add_option("--input", tr.input, "Touches JSON (see engine/calibration/tracker_calibration.h)")
      ->required()
      ->check(CLI::ExistingFile);
  tracker_->add_option("--site", tr.site,
                       "Site file to update in place (start from a copy of assets/sites/default.json): "
                       "the tracker pose and its residual; the rest is kept")
      ->required();
  add_device_option(*tracker_, unused_device_);
  tracker_->add_option("--inlier-threshold-mm", tr.inlier_threshold_mm,
                       "A touch farther than this from its screen point is rejected")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();

  SynthesizeCommandOptions& sy = synthesize_options_;
  const calibration::SyntheticSiteOptions defaults;
  sy.out = "out/calibration/synthetic";
  sy.corner_noise_px = defaults.corner_noise_px;
  sy.distance_noise_mm = defaults.distance_noise_mm;
  sy.tip_noise_mm = defaults.tip_noise_mm;
  sy.tip_outliers = defaults.tip_outliers;
  sy.seed = defaults.seed;
  synthesize_ = command_->add_subcommand(
      "synthesize", "Write the inputs of `calibrate extrinsics` and `calibrate tracker` for a simulated site, "
                    "with its true calibration, to try and check the calibration");
  synthesize_->add_option("--out", sy.out, "Folder to write")->capture_default_str();
  add_device_option(*synthesize_, unused_device_);
  synthesize_->add_option("--corner-noise-px", sy.corner_noise_px, "Noise on the chessboard corners (sigma)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  synthesize_->add_option("--distance-noise-mm", sy.distance_noise_mm, "Noise on the measured distances (sigma)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  synthesize_->add_option("--tip-noise-mm", sy.tip_noise_mm, "Noise on the fingertip positions (sigma, per axis)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  synthesize_->add_option("--tip-outliers", sy.tip_outliers, "Touches that slipped by 30 to 60 mm")
      ->check(CLI::Range(0, 20))
      ->capture_default_str();
  synthesize_->add_option("--seed", sy.seed, "Random seed")->capture_default_str();
}

int CalibrateCommand::run() const {
  if (intrinsics_->parsed()) return run_calibrate_intrinsics(intrinsics_options_);
  if (extrinsics_->parsed()) return run_calibrate_extrinsics(extrinsics_options_);
  if (tracker_->parsed()) return run_calibrate_tracker(tracker_options_);
  if (synthesize_->parsed()) return run_calibrate_synthesize(synthesize_options_);
  return 1;
}

}  // namespace rt::app
