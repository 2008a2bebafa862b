#pragma once
// A simulated site with known ground truth for the calibration: the default site
// (sim/default_site.h) with its camera stand a little farther from the glass and real lenses,
// a chessboard held up in front of the screen in many poses (its corners as each camera that
// sees it whole would find them, with noise),
// tape-measured distances from each camera to the screen corners (with noise), and a grid of
// fingertip touches on the glass the tracker sees, as it would report them (with noise and a few
// slipped touches). Used by the tests and by `remotetouch calibrate synthesize`.
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <vector>

#include "calibration/extrinsics_input.h"
#include "calibration/tracker_calibration.h"
#include "sim/site_description.h"

namespace rt::calibration {

struct SyntheticSiteOptions {
  double corner_noise_px = 0.1;     // Gaussian, per corner coordinate
  double distance_noise_mm = 1.0;   // Gaussian, per measured distance
  double tip_noise_mm = 2.0;        // Gaussian, per fingertip coordinate
  size_t tip_outliers = 3;          // touches displaced by 30 to 60 mm
  size_t board_poses = 24;
  uint32_t seed = 1;
};

struct SyntheticSite {
  sim::SiteDescription truth;        // a valid site file: what a perfect calibration would write
  ExtrinsicsInput extrinsics_input;  // views as corners_px, noisy distances
  std::vector<Eigen::Isometry3d> site_from_board;  // where the board was held in each view
  std::vector<TrackerTouch> touches;
  std::vector<bool> touch_is_outlier;
};

SyntheticSite make_synthetic_site(const SyntheticSiteOptions& options = {});

// Writes the inputs of the calibrate commands and the truth into `folder`:
// extrinsics_input.json (naming intrinsics/<camera>.json), tracker_touches.json,
// truth_site.json (a site file) and truth_touch_outliers.json.
void write_synthetic_site(const SyntheticSite& site, const std::filesystem::path& folder);

}  // namespace rt::calibration
