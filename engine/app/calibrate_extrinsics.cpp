// `remotetouch calibrate extrinsics`: the cameras' poses in the site frame, written into the
// site file.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/calibrate.h"
#include "calibration/extrinsics_calibration.h"
#include "calibration/site_update.h"

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

}  // namespace

int run_calibrate_extrinsics(const ExtrinsicsCommandOptions& options) {
  const calibration::ExtrinsicsInput input = calibration::read_extrinsics_input(options.input);
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

}  // namespace rt::app
