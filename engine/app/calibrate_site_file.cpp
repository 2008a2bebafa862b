#include "app/calibrate_site_file.h"

#include <stdexcept>

namespace rt::app {

SiteCalibration load_site_calibration_to_update(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) return {};
  try {
    return read_site_calibration(path);
  } catch (const std::exception& error) {
    throw std::runtime_error("--out '" + path.string() + "' exists but is not a site calibration to update (" +
                             error.what() + "); remove it or choose another --out");
  }
}

}  // namespace rt::app
