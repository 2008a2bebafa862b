#include "calibration/site_calibration.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "config/json_fields.h"

namespace rt {
namespace {

using config::JsonError;

// The unit the tracker's native positions are read in; the only one the Leap protocol has.
constexpr const char* kTrackerUnit = "mm";

Screen screen_from_json(const nlohmann::json& json, const std::string& where) {
  Screen screen;
  screen.width_m = config::require_positive(json, "width_m", where);
  screen.height_m = config::require_positive(json, "height_m", where);
  return screen;
}

TrackerPose tracker_from_json(const nlohmann::json& json, const std::string& where) {
  const std::string unit = config::require_string(json, "tracker_unit", where);
  if (unit != kTrackerUnit)
    throw JsonError(where + ": field 'tracker_unit' is '" + unit + "', only '" + kTrackerUnit + "' is known");
  TrackerPose tracker;
  tracker.site_from_tracker =
      isometry_from_json(config::require(json, "site_from_tracker", where), where + " site_from_tracker");
  if (json.contains("rms_residual_mm")) {
    tracker.rms_residual_mm = config::require_number(json, "rms_residual_mm", where);
    if (tracker.rms_residual_mm < 0) throw JsonError(where + ": field 'rms_residual_mm' must be >= 0");
  }
  return tracker;
}

// JSON has no NaN: nlohmann writes null, which no reader would take for a number.
void check_finite(const SiteCalibration& calibration) {
  auto fail = [](const std::string& what) { throw JsonError("site calibration: " + what + " is not finite; not written"); };
  if (!std::isfinite(calibration.screen.width_m) || !std::isfinite(calibration.screen.height_m)) fail("the screen size");
  for (const Camera& camera : calibration.cameras) {
    const CameraIntrinsics& k = camera.intrinsics;
    bool finite = std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) && std::isfinite(k.cy) &&
                  camera.camera_from_site.matrix().allFinite();
    for (double c : k.distortion.as_opencv()) finite = finite && std::isfinite(c);
    if (!finite) fail("camera '" + camera.name + "'");
  }
  if (calibration.tracker && (!calibration.tracker->site_from_tracker.matrix().allFinite() ||
                              !std::isfinite(calibration.tracker->rms_residual_mm)))
    fail("the tracker pose");
}

}  // namespace

const Camera* SiteCalibration::find_camera(const std::string& name) const {
  const auto it = std::find_if(cameras.begin(), cameras.end(), [&](const Camera& c) { return c.name == name; });
  return it == cameras.end() ? nullptr : &*it;
}

nlohmann::json site_calibration_to_json(const SiteCalibration& calibration) {
  nlohmann::json json;
  json["screen"] = {{"width_m", calibration.screen.width_m}, {"height_m", calibration.screen.height_m}};
  json["cameras"] = nlohmann::json::array();
  for (const Camera& camera : calibration.cameras) json["cameras"].push_back(camera_to_json(camera));
  if (calibration.tracker)
    json["tracker"] = {{"site_from_tracker", isometry_to_json(calibration.tracker->site_from_tracker)},
                       {"tracker_unit", kTrackerUnit},
                       {"rms_residual_mm", calibration.tracker->rms_residual_mm}};
  return json;
}

SiteCalibration site_calibration_from_json(const nlohmann::json& json, const std::string& where) {
  if (!json.is_object()) throw JsonError(where + ": expected an object with 'screen', 'cameras', 'tracker'");
  SiteCalibration calibration;
  calibration.screen = screen_from_json(config::require(json, "screen", where), where + " screen");
  if (json.contains("cameras")) {
    std::set<std::string> names;
    for (const nlohmann::json& entry : config::require_array(json, "cameras", where)) {
      Camera camera;
      try {
        camera = camera_from_json(entry);
      } catch (const JsonError& error) {
        throw JsonError(where + ": " + error.what());
      }
      if (!entry.contains("camera_from_site"))
        throw JsonError(where + ": camera '" + camera.name + "': missing field 'camera_from_site'");
      if (!names.insert(camera.name).second)
        throw JsonError(where + ": camera name '" + camera.name + "' appears twice");
      calibration.cameras.push_back(std::move(camera));
    }
  }
  if (json.contains("tracker")) calibration.tracker = tracker_from_json(json["tracker"], where + " tracker");
  return calibration;
}

SiteCalibration read_site_calibration(const std::filesystem::path& path) {
  return site_calibration_from_json(config::read_json_file(path), "site calibration '" + path.string() + "'");
}

void write_site_calibration(const std::filesystem::path& path, const SiteCalibration& calibration) {
  check_finite(calibration);
  config::write_json_file(path, site_calibration_to_json(calibration));
}

}  // namespace rt
