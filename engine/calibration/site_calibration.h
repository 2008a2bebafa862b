#pragma once
// The calibration of one site, as the rest of the system reads it: the screen, every camera
// (intrinsics and camera-from-site pose) and the hand tracker's pose. One JSON file per site,
// written step by step by `remotetouch calibrate extrinsics` and `calibrate tracker`.
//
// {"screen": {"width_m", "height_m"},
//  "cameras": [rt::camera_to_json, "camera_from_site" required],
//  "tracker": {"site_from_tracker": 4x4 row-major, "tracker_unit": "mm", "rms_residual_mm"}}
// "cameras" and "tracker" may be absent while the site is only partly calibrated.
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "geometry/site_frames.h"

namespace rt {

// Tracker-native positions (Leap style: millimetres, y up, origin on the device) are converted
// to metres first, then mapped by the rigid site_from_tracker.
struct TrackerPose {
  Eigen::Isometry3d site_from_tracker = Eigen::Isometry3d::Identity();  // metres to metres
  double rms_residual_mm = 0;  // of the touches that calibrated it, for the record

  Eigen::Vector3d to_site(const Eigen::Vector3d& tracker_mm) const { return site_from_tracker * (tracker_mm * 1e-3); }
};

struct SiteCalibration {
  Screen screen;
  std::vector<Camera> cameras;
  std::optional<TrackerPose> tracker;

  const Camera* find_camera(const std::string& name) const;
};

nlohmann::json site_calibration_to_json(const SiteCalibration& calibration);
// Errors (config::JsonError) name `where`, the field and what is wrong with it.
SiteCalibration site_calibration_from_json(const nlohmann::json& json, const std::string& where);

SiteCalibration read_site_calibration(const std::filesystem::path& path);
void write_site_calibration(const std::filesystem::path& path, const SiteCalibration& calibration);

}  // namespace rt
