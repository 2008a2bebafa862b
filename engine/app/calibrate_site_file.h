#pragma once
// The site calibration file that `calibrate extrinsics` and `calibrate tracker` each fill in
// part of: the one step's result replaces its part, the other part is kept.
#include <filesystem>

#include "calibration/site_calibration.h"

namespace rt::app {

// The existing file at `path`, or an empty calibration when there is none. An existing file
// that is not a site calibration is an error: it is not overwritten.
SiteCalibration load_site_calibration_to_update(const std::filesystem::path& path);

}  // namespace rt::app
