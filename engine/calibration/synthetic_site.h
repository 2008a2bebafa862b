#pragma once
// A simulated site with known ground truth for the calibration: six cameras on a stand around
// the 65-inch screen looking at the seated user, a chessboard held up in front of the screen
// in many poses (its corners as each camera that sees it whole would find them, with noise),
// tape-measured distances from each camera to the screen corners (with noise), and a grid of
// fingertip touches on the screen as the tracker would report them (with noise and a few
// slipped touches). Used by the tests and by `remotetouch calibrate synthesize`.
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <vector>

#include "calibration/extrinsics_input.h"
#include "calibration/site_calibration.h"
#include "calibration/tracker_calibration.h"

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
  SiteCalibration truth;
  ExtrinsicsInput extrinsics_input;  // views as corners_px, noisy distances
  std::vector<TrackerTouch> touches;
  std::vector<bool> touch_is_outlier;
};

SyntheticSite make_synthetic_site(const SyntheticSiteOptions& options = {});

// The camera-from-site pose of a camera at `position` looking at `target`, image x to the
// right as seen from the camera, with the site's +y as up.
Eigen::Isometry3d camera_looking_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target);

// Writes the inputs of the calibrate commands and the truth into `folder`:
// extrinsics_input.json (naming intrinsics/<camera>.json), tracker_touches.json,
// truth_site_calibration.json.
void write_synthetic_site(const SyntheticSite& site, const std::filesystem::path& folder);

}  // namespace rt::calibration
