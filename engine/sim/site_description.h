#pragma once
// What is physically at one site (DESIGN.md section 1), in the site frame (metres): the screen,
// where the user sits, six RGBD cameras on the stand, the hand tracker, the vibration motor.
// This is the one site file of the system: the shipped ones (assets/sites/*.json) are generated
// by default_site.h; a real site starts from a copy that `remotetouch calibrate extrinsics` and
// `calibrate tracker` update in place (calibration/site_update.h), and every consumer (the
// simulator, recordings, the site pipeline) reads it with load_site().
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/camera.h"
#include "geometry/site_frames.h"

namespace rt::sim {

// One Azure-Kinect-like RGBD camera. Color and depth share one pose in our model: the real
// device's depth camera sits a few centimetres from its color camera with its own extrinsic;
// the simulator renders both from the same centre so that the lead's renderer needs one view
// matrix per camera, and calibration code sees the ideal, registered case.
struct RgbdCamera {
  std::string name;
  Eigen::Isometry3d camera_from_site = Eigen::Isometry3d::Identity();  // OpenCV axes: x right, y down, z forward
  CameraIntrinsics color;
  CameraIntrinsics depth;
  double depth_min_m = 0.25;  // WFOV 2x2-binned operating range
  double depth_max_m = 2.88;
  // Where its frames come from: "simulated" (the simulator renders them), "k4a" (a live Azure
  // Kinect or Orbbec Femto, its settings in `k4a`, read by devices/camera/site_camera_sources.h)
  // or "k4a-recording:PATH" (a recording of one; a relative path is from the site file's folder).
  std::string source = "simulated";
  nlohmann::json k4a = nlohmann::json::object();
  // A real camera's colour lens is its device's factory calibration at the recorded mode, unless
  // the site file says "color_lens": "site-file" (a lens calibrated by hand with `calibrate
  // intrinsics`): then the colour intrinsics above are used, for the same image size.
  bool color_lens_from_site_file = false;

  Camera color_camera() const;
  Camera depth_camera() const;
  // Inside both image rectangles and the depth range: the point gets a color and a depth sample.
  bool sees(const Eigen::Vector3d& site_point) const;
  // Empty when `sees`, else why not ("outside the color image", "beyond the depth range", ...).
  std::string why_unseen(const Eigen::Vector3d& site_point) const;
};

// The tracker's tracking volume in its own frame: a range of distances from the device and a
// field of view about its +y axis (Leap Motion Controller: about 140 x 120 degrees).
struct TrackingRange {
  double min_distance_m = 0.07;
  double max_distance_m = 0.80;
  double half_angle_x_deg = 70.0;  // in the device's x-y plane
  double half_angle_z_deg = 60.0;  // in the device's z-y plane
  bool contains(const Eigen::Vector3d& point_in_tracker_m) const;
};

// Leap-style device frame: origin on the device, +y out of its face, +x to the user's right,
// +z towards the user. The rigid transform is in metres and stored as site_from_tracker, the way
// the tracker calibration finds it; the device itself reports its frame scaled to millimetres
// (see tracker_space.h).
struct TrackerPlacement {
  Eigen::Isometry3d site_from_tracker = Eigen::Isometry3d::Identity();
  TrackingRange range;
  // RMS distance of the calibration touches from their screen points; absent until calibrated.
  std::optional<double> rms_residual_mm;

  Eigen::Isometry3d tracker_from_site() const { return site_from_tracker.inverse(); }
  bool sees(const Eigen::Vector3d& site_point) const { return range.contains(tracker_from_site() * site_point); }
};

// Where the seated user's head rests (its centre, about eye height).
struct Seat {
  Eigen::Vector3d head_centre_m = Eigen::Vector3d(0.0, 0.1, 0.7);
  // The middle of the chest, which every camera of a site must see (a camera that does not is
  // turned the wrong way or miscalibrated): the one part of the user both camera rows look at.
  Eigen::Vector3d chest_m() const { return head_centre_m - Eigen::Vector3d(0.0, 0.3, 0.0); }
};

// The part of the glass where the user is expected to touch; the tracker must cover it.
struct TouchRegion {
  Eigen::Vector2d centre_m = Eigen::Vector2d(0.1, 0.0);
  Eigen::Vector2d half_size_m = Eigen::Vector2d(0.2, 0.15);
  // Points the tracker must see: the region's centre and corners at the given heights above the glass.
  std::vector<Eigen::Vector3d> sample_points(double height_m) const;
};

struct SiteDescription {
  std::string name;
  Screen screen;
  Seat seat;
  std::vector<RgbdCamera> cameras;
  TrackerPlacement tracker;
  TouchRegion touch_region;
  Eigen::Vector3d motor_position_m = Eigen::Vector3d::Zero();

  const RgbdCamera* find_camera(std::string_view camera_name) const;
};

// Heights above the glass at which the tracker must see the whole touch region: from a palm
// pressed on the glass to a hand about to touch.
inline constexpr double kTouchRegionLowM = 0.005;
inline constexpr double kTouchRegionHighM = 0.15;

nlohmann::json site_to_json(const SiteDescription& site);
// Parses and validates; errors start with `where` and name the field or the camera.
SiteDescription site_from_json(const nlohmann::json& json, const std::string& where);
// Errors name the file.
SiteDescription load_site(const std::filesystem::path& path);
// Validates first and refuses non-finite numbers (JSON has no NaN); nothing is written then.
void write_site(const std::filesystem::path& path, const SiteDescription& site);
// Geometry that a well-formed file can still get wrong: every camera sees the seated user's
// head, the tracker sees the touch region, camera names are unique. Throws config::JsonError.
void validate_site(const SiteDescription& site, const std::string& where);

}  // namespace rt::sim
