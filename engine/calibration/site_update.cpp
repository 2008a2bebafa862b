#include "calibration/site_update.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calibration/calibration_error.h"
#include "config/json.h"

namespace rt::calibration {
namespace {

std::string camera_names_text(const sim::SiteDescription& site) {
  std::string names;
  for (const sim::RgbdCamera& camera : site.cameras) names += (names.empty() ? "'" : ", '") + camera.name + "'";
  return names;
}

std::string screen_text(const Screen& screen) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f x %.3f m", screen.width_m, screen.height_m);
  return text;
}

}  // namespace

sim::SiteDescription load_site_to_update(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw CalibrationError("site file '" + path.string() +
                           "' does not exist: start from a copy of assets/sites/default.json and edit its screen, "
                           "seat, touch region and camera names to match the site");
  try {
    return sim::load_site(path);
  } catch (const std::exception& error) {
    throw CalibrationError("'" + path.string() + "' is not a site file to update (" + error.what() +
                           "); it is left as it is");
  }
}

void check_cameras_fit_site(const sim::SiteDescription& site, const std::vector<std::string>& camera_names,
                            const Screen& calibrated_screen) {
  if (std::abs(calibrated_screen.width_m - site.screen.width_m) > kScreenSizeToleranceM ||
      std::abs(calibrated_screen.height_m - site.screen.height_m) > kScreenSizeToleranceM)
    throw CalibrationError("the cameras are calibrated against a " + screen_text(calibrated_screen) +
                           " screen, the site file has " + screen_text(site.screen) +
                           "; give the same 'screen' in the extrinsics input and the site file");
  for (const std::string& name : camera_names)
    if (!site.find_camera(name))
      throw CalibrationError("camera '" + name + "' is not in the site file (its cameras: " + camera_names_text(site) +
                             "); name the cameras alike in both");
}

std::vector<std::string> apply_camera_calibration(sim::SiteDescription& site, const ExtrinsicsResult& result,
                                                  const Screen& calibrated_screen) {
  std::vector<std::string> calibrated;
  for (const PlacedCamera& placed : result.cameras) calibrated.push_back(placed.camera.name);
  check_cameras_fit_site(site, calibrated, calibrated_screen);
  std::vector<std::string> not_calibrated;
  for (sim::RgbdCamera& camera : site.cameras) {
    const auto placed = std::find_if(result.cameras.begin(), result.cameras.end(),
                                     [&](const PlacedCamera& p) { return p.camera.name == camera.name; });
    if (placed == result.cameras.end()) {
      not_calibrated.push_back(camera.name);
      continue;
    }
    camera.color = placed->camera.intrinsics;
    camera.camera_from_site = placed->camera.camera_from_site;
  }
  return not_calibrated;
}

void apply_tracker_calibration(sim::SiteDescription& site, const TrackerCalibration& result) {
  site.tracker.site_from_tracker = result.site_from_tracker;
  site.tracker.rms_residual_mm = result.inlier_rms_mm;
}

void write_updated_site(const std::filesystem::path& path, const sim::SiteDescription& site) {
  try {
    sim::write_site(path, site);
  } catch (const config::JsonError& error) {
    throw CalibrationError(std::string("the calibrated site fails its checks, '") + path.string() +
                           "' is left as it was: " + error.what());
  }
}

}  // namespace rt::calibration
