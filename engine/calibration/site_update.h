#pragma once
// Calibration results written into the one site file (sim/site_description.h): a real site
// starts from a copy of assets/sites/default.json, and each calibration step replaces only the
// parts it measured. `calibrate extrinsics` replaces the cameras' color intrinsics and poses,
// matched by name; `calibrate tracker` replaces the tracker pose and its residual. The seat,
// the touch region, the motor, the depth intrinsics and ranges, and the tracking range are kept.
#include <filesystem>
#include <string>
#include <vector>

#include "calibration/extrinsics_calibration.h"
#include "calibration/tracker_calibration.h"
#include "geometry/site_frames.h"
#include "sim/site_description.h"

namespace rt::calibration {

// Screens that differ by more than this are different screens, not a rounding difference.
inline constexpr double kScreenSizeToleranceM = 1e-3;

// The site file at `path`, to be updated. Throws CalibrationError, saying how to get one, when
// it is missing or is not a site file (it is then never overwritten).
sim::SiteDescription load_site_to_update(const std::filesystem::path& path);

// Throws CalibrationError, naming the camera and the site's cameras, when a camera to be
// calibrated is not in the site, and when the calibration's screen is not the site's.
void check_cameras_fit_site(const sim::SiteDescription& site, const std::vector<std::string>& camera_names,
                            const Screen& calibrated_screen);

// Replaces the color intrinsics and camera_from_site of every calibrated camera, by name, after
// check_cameras_fit_site (a refusal leaves the site untouched). Returns the names of the site's
// cameras that the calibration did not include (left as they were).
std::vector<std::string> apply_camera_calibration(sim::SiteDescription& site, const ExtrinsicsResult& result,
                                                  const Screen& calibrated_screen);

void apply_tracker_calibration(sim::SiteDescription& site, const TrackerCalibration& result);

// write_site, with its check failures (a calibrated camera that does not see the seat, a
// tracker that does not see the touch region) as CalibrationError: nothing is written then.
void write_updated_site(const std::filesystem::path& path, const sim::SiteDescription& site);

}  // namespace rt::calibration
