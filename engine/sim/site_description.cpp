#include "sim/site_description.h"

#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "config/json.h"

namespace rt::sim {

using namespace config;  // the JSON readers

using config::JsonError;

namespace {

std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream text;
  text << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return text.str();
}

bool inside_image(const Eigen::Vector2d& pixel, const CameraIntrinsics& k) {
  // Pixel centres are at integer coordinates (OpenCV): the image spans [-0.5, size - 0.5].
  return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() <= k.width - 0.5 && pixel.y() <= k.height - 0.5;
}

void check_principal_point(const CameraIntrinsics& k, const std::string& where) {
  if (k.cx < 0 || k.cx > k.width || k.cy < 0 || k.cy > k.height)
    throw JsonError(where + ": principal point (cx, cy) lies outside the " + std::to_string(k.width) + "x" +
                    std::to_string(k.height) + " image");
}

nlohmann::json depth_to_json(const RgbdCamera& camera) {
  nlohmann::json depth = intrinsics_to_json(camera.depth);
  depth["min_range_m"] = camera.depth_min_m;
  depth["max_range_m"] = camera.depth_max_m;
  return depth;
}

RgbdCamera camera_entry_from_json(const nlohmann::json& entry, const std::string& where) {
  if (!entry.is_object()) throw JsonError(where + ": must be an object");
  const std::string name = config::require_string(entry, "name", where);
  const std::string camera_where = where + " (camera '" + name + "')";
  reject_unknown_fields(
      entry, {"name", "width", "height", "fx", "fy", "cx", "cy", "distortion", "camera_from_site", "depth", "source", "k4a",
              "color_lens"},
      camera_where);
  // camera_from_json treats a missing pose as the identity; a site camera must say where it is.
  config::require(entry, "camera_from_site", camera_where);
  Camera color;
  try {
    color = camera_from_json(entry);
  } catch (const JsonError& error) {
    throw JsonError(where + ": " + error.what());
  }

  RgbdCamera camera;
  camera.name = name;
  if (entry.contains("source")) {
    camera.source = config::require_string(entry, "source", camera_where);
    const bool recording = camera.source.starts_with("k4a-recording:");
    if (camera.source != "simulated" && camera.source != "k4a" && !recording)
      throw JsonError(camera_where + ": source '" + camera.source +
                      "' is none of \"simulated\", \"k4a\" (a live device) and \"k4a-recording:PATH\"");
    if (recording && camera.source.size() == std::string_view("k4a-recording:").size())
      throw JsonError(camera_where + ": source \"k4a-recording:\" names no file (k4a-recording:PATH)");
  }
  if (entry.contains("k4a")) {
    if (camera.source != "k4a")
      throw JsonError(camera_where + ": has k4a settings, which only a live camera (source \"k4a\") uses");
    camera.k4a = require_object(entry, "k4a", camera_where);
  } else if (camera.source == "k4a") {
    throw JsonError(camera_where + ": a live camera (source \"k4a\") needs its device's settings in \"k4a\" "
                    "(at least its \"serial\")");
  }
  if (entry.contains("color_lens")) {
    const std::string lens = config::require_string(entry, "color_lens", camera_where);
    if (lens != "factory" && lens != "site-file")
      throw JsonError(camera_where + ": color_lens '" + lens +
                      "' is neither \"factory\" (the device's calibration) nor \"site-file\" (the intrinsics here)");
    camera.color_lens_from_site_file = lens == "site-file";
  }
  camera.camera_from_site = color.camera_from_site;
  camera.color = color.intrinsics;
  check_principal_point(camera.color, camera_where);

  const std::string depth_where = camera_where + " depth";
  const nlohmann::json& depth = require_object(entry, "depth", camera_where);
  reject_unknown_fields(depth, {"width", "height", "fx", "fy", "cx", "cy", "distortion", "min_range_m", "max_range_m"},
                        depth_where);
  camera.depth = intrinsics_from_json(depth, depth_where);
  check_principal_point(camera.depth, depth_where);
  camera.depth_min_m = config::require_positive(depth, "min_range_m", depth_where);
  camera.depth_max_m = config::require_positive(depth, "max_range_m", depth_where);
  if (camera.depth_max_m <= camera.depth_min_m)
    throw JsonError(depth_where + ": field 'max_range_m' must be greater than 'min_range_m'");
  return camera;
}

nlohmann::json tracker_to_json(const TrackerPlacement& tracker) {
  const TrackingRange& range = tracker.range;
  nlohmann::json json = {{"site_from_tracker", isometry_to_json(tracker.site_from_tracker)},
                         {"range",
                          {{"min_distance_m", range.min_distance_m},
                           {"max_distance_m", range.max_distance_m},
                           {"half_angle_x_deg", range.half_angle_x_deg},
                           {"half_angle_z_deg", range.half_angle_z_deg}}}};
  if (tracker.rms_residual_mm) json["rms_residual_mm"] = *tracker.rms_residual_mm;
  return json;
}

// JSON has no NaN: nlohmann writes null, which no reader would take for a number.
void check_finite(const nlohmann::json& json, const std::string& where, const std::string& path = "") {
  if (json.is_number_float() && !std::isfinite(json.get<double>()))
    throw JsonError(where + ": " + path + " is not finite; not written");
  if (json.is_object())
    for (const auto& [key, value] : json.items()) check_finite(value, where, path.empty() ? key : path + "/" + key);
  if (json.is_array())
    for (size_t i = 0; i < json.size(); ++i) check_finite(json[i], where, path + "/" + std::to_string(i));
}

}  // namespace

Camera RgbdCamera::color_camera() const { return Camera{name + " color", color, camera_from_site}; }

Camera RgbdCamera::depth_camera() const { return Camera{name + " depth", depth, camera_from_site}; }

std::string RgbdCamera::why_unseen(const Eigen::Vector3d& site_point) const {
  const Eigen::Vector3d in_camera = camera_from_site * site_point;
  if (!(in_camera.z() > 0)) return "it is behind the camera";
  const auto color_pixel = color_camera().project(site_point);
  if (!color_pixel || !inside_image(*color_pixel, color)) return "it is outside the color image";
  const auto depth_pixel = depth_camera().project(site_point);
  if (!depth_pixel || !inside_image(*depth_pixel, depth)) return "it is outside the depth image";
  // The Azure Kinect's depth is the z coordinate, not the distance along the ray.
  if (in_camera.z() < depth_min_m) return "it is closer than the depth range (" + format_number(depth_min_m) + " m)";
  if (in_camera.z() > depth_max_m) return "it is beyond the depth range (" + format_number(depth_max_m) + " m)";
  return {};
}

bool RgbdCamera::sees(const Eigen::Vector3d& site_point) const { return why_unseen(site_point).empty(); }

bool TrackingRange::contains(const Eigen::Vector3d& p) const {
  const double distance = p.norm();
  if (!(distance >= min_distance_m && distance <= max_distance_m) || !(p.y() > 0)) return false;
  constexpr double kDegrees = 180.0 / std::numbers::pi;
  return std::atan2(std::abs(p.x()), p.y()) * kDegrees <= half_angle_x_deg &&
         std::atan2(std::abs(p.z()), p.y()) * kDegrees <= half_angle_z_deg;
}

std::vector<Eigen::Vector3d> TouchRegion::sample_points(double height_m) const {
  std::vector<Eigen::Vector3d> points{{centre_m.x(), centre_m.y(), height_m}};
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      points.emplace_back(centre_m.x() + sx * half_size_m.x(), centre_m.y() + sy * half_size_m.y(), height_m);
  return points;
}

const RgbdCamera* SiteDescription::find_camera(std::string_view camera_name) const {
  for (const RgbdCamera& camera : cameras)
    if (camera.name == camera_name) return &camera;
  return nullptr;
}

nlohmann::json site_to_json(const SiteDescription& site) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const RgbdCamera& camera : site.cameras) {
    nlohmann::json entry = camera_to_json(camera.color_camera());
    entry["name"] = camera.name;
    entry["depth"] = depth_to_json(camera);
    if (camera.source != "simulated") entry["source"] = camera.source;
    if (!camera.k4a.empty()) entry["k4a"] = camera.k4a;
    if (camera.color_lens_from_site_file) entry["color_lens"] = "site-file";
    cameras.push_back(entry);
  }
  return {
      {"name", site.name},
      {"screen", {{"width_m", site.screen.width_m}, {"height_m", site.screen.height_m}}},
      {"seat", {{"head_centre_m", to_json(site.seat.head_centre_m)}}},
      {"cameras", cameras},
      {"tracker", tracker_to_json(site.tracker)},
      {"touch_region",
       {{"centre_m", to_json(site.touch_region.centre_m)}, {"half_size_m", to_json(site.touch_region.half_size_m)}}},
      {"motor", {{"position_m", to_json(site.motor_position_m)}}},
  };
}

SiteDescription site_from_json(const nlohmann::json& json, const std::string& where) {
  using namespace config;
  reject_unknown_fields(json, {"name", "screen", "seat", "cameras", "tracker", "touch_region", "motor"}, where);
  SiteDescription site;
  site.name = require_string(json, "name", where);

  const nlohmann::json& screen = require_object(json, "screen", where);
  reject_unknown_fields(screen, {"width_m", "height_m"}, where + " screen");
  site.screen.width_m = require_positive(screen, "width_m", where + " screen");
  site.screen.height_m = require_positive(screen, "height_m", where + " screen");

  const nlohmann::json& seat = require_object(json, "seat", where);
  reject_unknown_fields(seat, {"head_centre_m"}, where + " seat");
  site.seat.head_centre_m = require_vec3(seat, "head_centre_m", where + " seat");
  if (!(site.seat.head_centre_m.z() > 0))
    throw JsonError(where + " seat: field 'head_centre_m' must be in front of the screen (z > 0)");

  const nlohmann::json& cameras = require_array(json, "cameras", where, 1);
  for (size_t i = 0; i < cameras.size(); ++i)
    site.cameras.push_back(camera_entry_from_json(cameras[i], where + " cameras[" + std::to_string(i) + "]"));

  const std::string tracker_where = where + " tracker";
  const nlohmann::json& tracker = require_object(json, "tracker", where);
  // Files written before the convention became the calibration's own carry the inverse pose.
  if (tracker.contains("tracker_from_site"))
    throw JsonError(tracker_where +
                    ": field 'tracker_from_site' is the old convention; the site file stores the tracker pose as "
                    "'site_from_tracker' (its inverse), as `remotetouch calibrate tracker` writes it");
  reject_unknown_fields(tracker, {"site_from_tracker", "rms_residual_mm", "range"}, tracker_where);
  site.tracker.site_from_tracker =
      isometry_from_json(require(tracker, "site_from_tracker", tracker_where), tracker_where + " site_from_tracker");
  if (tracker.contains("rms_residual_mm"))
    site.tracker.rms_residual_mm = require_in_range(tracker, "rms_residual_mm", tracker_where, 0.0, 1000.0);
  const std::string range_where = tracker_where + " range";
  const nlohmann::json& range = require_object(tracker, "range", tracker_where);
  reject_unknown_fields(range, {"min_distance_m", "max_distance_m", "half_angle_x_deg", "half_angle_z_deg"}, range_where);
  TrackingRange& r = site.tracker.range;
  r.min_distance_m = require_in_range(range, "min_distance_m", range_where, 0.0, 10.0);
  r.max_distance_m = require_in_range(range, "max_distance_m", range_where, 0.0, 10.0);
  if (r.max_distance_m <= r.min_distance_m)
    throw JsonError(range_where + ": field 'max_distance_m' must be greater than 'min_distance_m'");
  r.half_angle_x_deg = require_in_range(range, "half_angle_x_deg", range_where, 1.0, 90.0);
  r.half_angle_z_deg = require_in_range(range, "half_angle_z_deg", range_where, 1.0, 90.0);

  const nlohmann::json& touch = require_object(json, "touch_region", where);
  reject_unknown_fields(touch, {"centre_m", "half_size_m"}, where + " touch_region");
  site.touch_region.centre_m = require_vec2(touch, "centre_m", where + " touch_region");
  site.touch_region.half_size_m = require_vec2(touch, "half_size_m", where + " touch_region");
  if ((site.touch_region.half_size_m.array() < 0).any())
    throw JsonError(where + " touch_region: field 'half_size_m' must not be negative");

  const nlohmann::json& motor = require_object(json, "motor", where);
  reject_unknown_fields(motor, {"position_m"}, where + " motor");
  site.motor_position_m = require_vec3(motor, "position_m", where + " motor");

  validate_site(site, where);
  return site;
}

void validate_site(const SiteDescription& site, const std::string& where) {
  std::set<std::string> names;
  for (const RgbdCamera& camera : site.cameras) {
    if (!names.insert(camera.name).second) throw JsonError(where + ": two cameras are named '" + camera.name + "'");
    const std::string why = camera.why_unseen(site.seat.chest_m());
    if (!why.empty())
      throw JsonError(where + ": camera '" + camera.name + "' cannot see the seated user's chest at " +
                      point_text(site.seat.chest_m()) + ": " + why);
  }
  const Eigen::Vector2d half_screen(site.screen.width_m / 2, site.screen.height_m / 2);
  const Eigen::Vector2d region_far_corner = site.touch_region.centre_m.cwiseAbs() + site.touch_region.half_size_m;
  if ((region_far_corner.array() > half_screen.array()).any())
    throw JsonError(where + " touch_region: reaches beyond the screen rectangle");
  for (double height : {kTouchRegionLowM, kTouchRegionHighM})
    for (const Eigen::Vector3d& point : site.touch_region.sample_points(height))
      if (!site.tracker.sees(point))
        throw JsonError(where + " tracker: does not see the touch region at " + point_text(point) +
                        " (outside its tracking range); move or turn the tracker, or shrink touch_region");
}

SiteDescription load_site(const std::filesystem::path& path) {
  // read_json_file reports unreadable JSON; a reader's own nlohmann exception (a value of the
  // wrong kind deep in the document) is named with the file here.
  try {
    const nlohmann::json json = config::read_json_file(path);
    return site_from_json(json, "site '" + path.string() + "'");
  } catch (const nlohmann::json::exception& error) {
    throw JsonError("site '" + path.string() + "': " + error.what());
  }
}

void write_site(const std::filesystem::path& path, const SiteDescription& site) {
  const std::string where = "site '" + path.string() + "'";
  const nlohmann::json json = site_to_json(site);
  check_finite(json, where);
  validate_site(site, where);
  config::write_json_file(path, json);
}

}  // namespace rt::sim
