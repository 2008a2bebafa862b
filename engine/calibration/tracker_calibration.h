#pragma once
// The hand tracker's pose in the site frame (the paper's method, after Ahuja et al. 2021): the
// user touches known points on the screen with the index fingertip, the tracker reports the
// tip in its own space (millimetres, y up), and the rigid transform that best maps the tips
// onto the points is found. Touches that disagree with the consensus (a slipped finger, a
// touch out of order) are rejected first: every minimal set of three touches proposes a
// transform, the one most touches agree with wins, and it is refined on those touches.
//
// Input file: {"touches": [{"label": "r0c0", "site_m": [x, y, z], "tip_mm": [x, y, z]}, ...]}
// with the screen point in the site frame (metres; z = 0 on the screen) and the fingertip in
// tracker space (millimetres). "label" is optional.
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace rt::calibration {

// A touch is an outlier when its tip lands farther than this from its screen point: with
// 2 mm noise per axis, 99.9 % of good touches stay within 8 mm.
constexpr double kDefaultInlierThresholdMm = 10.0;

struct TrackerTouch {
  std::string label;
  Eigen::Vector3d site_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();
};

struct TrackerCalibration {
  Eigen::Isometry3d site_from_tracker = Eigen::Isometry3d::Identity();  // metres to metres
  std::vector<double> residuals_mm;  // every touch, rejected ones included, against the final transform
  std::vector<bool> inlier;
  double inlier_rms_mm = 0;
  size_t inlier_count() const;
};

// Throws when there are fewer than 3 touches, the touches lie on a line, fewer than half of
// them (or fewer than 3) agree on one transform, or the tracker would end up behind the screen
// (which is how a mirrored, left-handed tip set fits a flat grid).
TrackerCalibration calibrate_tracker(const std::vector<TrackerTouch>& touches,
                                     double inlier_threshold_mm = kDefaultInlierThresholdMm);

std::vector<TrackerTouch> read_tracker_touches(const std::filesystem::path& path);
nlohmann::json tracker_touches_to_json(const std::vector<TrackerTouch>& touches);

}  // namespace rt::calibration
