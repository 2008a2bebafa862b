// `remotetouch calibrate extrinsics`: the cameras' poses in the site frame, written into the
// site file.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/calibrate.h"
#include "calibration/camera_network.h"
#include "calibration/extrinsics_calibration.h"
#include "calibration/screen_trilateration.h"
#include "calibration/site_update.h"
#include "camera/recorded_board_views.h"
#include "camera/recorded_site.h"

namespace rt::app {
namespace {

double largest_magnitude(const calibration::CornerDistances& values) {
  double largest = 0;
  for (double v : values) largest = std::max(largest, std::abs(v));
  return largest;
}

void print_report(const calibration::ExtrinsicsInput& input, const calibration::ExtrinsicsResult& result) {
  std::printf("%zu cameras, %zu views, reference camera '%s'\n", input.cameras.size(), input.snapshots.size(),
              input.reference_camera.c_str());
  if (!input.board_not_found.empty()) {
    std::printf("board not found in:\n");
    for (const auto& where : input.board_not_found) std::printf("  %s\n", where.c_str());
  }
  std::printf("%-16s %-16s %5s %9s %13s %11s  %s\n", "camera", "linked to", "views", "link RMS", "corner dist.",
              "alignment", "position in site (m)");
  for (const auto& placed : result.cameras) {
    const Eigen::Vector3d position = placed.camera.position_in_site();
    std::printf("%-16s %-16s %5zu %6.3f px %7.1f mm max %8.1f mm  (%+.3f, %+.3f, %+.3f)\n", placed.camera.name.c_str(),
                placed.link.linked_to.empty() ? "(reference)" : placed.link.linked_to.c_str(),
                placed.link.shared_views, placed.link.rms_error_px,
                largest_magnitude(placed.trilateration.residuals_m) * 1000.0, placed.alignment_residual_m * 1000.0,
                position.x(), position.y(), position.z());
  }
  std::printf("alignment RMS %.2f mm (chessboard positions against the positions from the distances)\n",
              result.alignment_rms_m * 1000.0);
}

calibration::ExtrinsicsInput extrinsics_input_for(const ExtrinsicsCommandOptions& options) {
  if (options.views_from.empty()) return calibration::read_extrinsics_input(options.input);
  calibration::ExtrinsicsInput input =
      calibration::read_extrinsics_input(options.input, calibration::ViewsFrom::Recording);
  const std::unique_ptr<sim::RecordedRgbdSource> recording = camera::open_recorded_site(options.views_from);
  std::printf("searching the board in %s (%s, %zu frame sets), a frame set every %.2f s\n",
              options.views_from.c_str(), camera::recorded_site_kind(options.views_from).c_str(),
              recording->frame_count(), options.view_every_s);
  const camera::RecordedBoardViews found = camera::add_recorded_board_views(
      input, *recording, options.view_every_s, "recording '" + options.views_from.string() + "'");
  std::printf("the board was found in %zu of %zu frame sets searched\n", found.views_added,
              found.frame_sets_searched);
  return input;
}

}  // namespace

int run_calibrate_extrinsics(const ExtrinsicsCommandOptions& options) {
  const calibration::ExtrinsicsInput input = extrinsics_input_for(options);
  const calibration::ExtrinsicsLimits limits{options.max_distance_residual_mm / 1000.0, options.max_link_rms_px,
                                             options.max_alignment_residual_mm / 1000.0};
  // Checked before calibrating so that a wrong --site fails at once, not after the solve.
  sim::SiteDescription site = calibration::load_site_to_update(options.site);
  std::vector<std::string> camera_names;
  for (const calibration::CameraSetup& camera : input.cameras) camera_names.push_back(camera.name);
  calibration::check_cameras_fit_site(site, camera_names, input.screen);
  const calibration::ExtrinsicsResult result = calibration::calibrate_extrinsics(input, limits);
  print_report(input, result);

  const std::vector<std::string> not_calibrated = calibration::apply_camera_calibration(site, result, input.screen);
  calibration::write_updated_site(options.site, site);
  std::printf("updated %s (%zu cameras: color intrinsics and poses; kept the tracker, seat, touch region, motor)\n",
              options.site.c_str(), result.cameras.size());
  for (const std::string& name : not_calibrated)
    std::printf("note: camera '%s' of the site file was not in the calibration input; left as it was\n", name.c_str());
  return 0;
}

namespace {

class CalibrateExtrinsicsCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    ExtrinsicsCommandOptions& ex = options_;
    ex.max_distance_residual_mm = calibration::kMaxCornerDistanceResidualM * 1000.0;
    ex.max_link_rms_px = calibration::kMaxLinkRmsPx;
    ex.max_alignment_residual_mm = calibration::kMaxAlignmentResidualM * 1000.0;
    CLI::App* command = parent.add_subcommand(
        "extrinsics", "The cameras' poses in the site frame, from simultaneous chessboard views and each camera's "
                      "measured distances to the four screen corners");
    command->add_option("--input", ex.input, "Extrinsics input JSON (see engine/calibration/extrinsics_input.h)")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("--site", ex.site,
                            "Site file to update in place (start from a copy of assets/sites/default.json): "
                            "each calibrated camera's color intrinsics and pose, by name; the rest is kept")
        ->required();
    command->add_option("--views-from", ex.views_from,
                            "A recording of the site's cameras (what `record` writes, or k4a recordings beside a "
                            "site.json) to take the chessboard views from, and each camera's factory intrinsics "
                            "unless the input gives them; the input may then leave out its views")
        ->check(CLI::ExistingDirectory);
    ex.view_every_s = 0.5;
    command->add_option("--view-every-s", ex.view_every_s,
                            "With --views-from: search one frame set every this many seconds of the recording "
                            "(0: every set)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    add_unused_device_option(*command, unused_device_);
    command->add_option("--max-distance-residual-mm", ex.max_distance_residual_mm,
                            "Largest disagreement between a camera's four corner distances")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_option("--max-link-rms-px", ex.max_link_rms_px,
                            "Largest RMS reprojection error of a camera pair's shared views")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_option("--max-alignment-residual-mm", ex.max_alignment_residual_mm,
                            "Largest distance between a camera's position from the chessboards and from the distances")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    return command;
  }
  int run() override { return run_calibrate_extrinsics(options_); }

 private:
  ExtrinsicsCommandOptions options_;
  std::string unused_device_;
};

}  // namespace

std::unique_ptr<Command> make_calibrate_extrinsics_command() { return std::make_unique<CalibrateExtrinsicsCommand>(); }

}  // namespace rt::app
