#include "camera/recorded_site.h"

#include <stdexcept>

#include "camera/k4a_site_recordings.h"
#include "sim/recording.h"

namespace rt::camera {

std::unique_ptr<sim::RecordedRgbdSource> open_recorded_site(const std::filesystem::path& dir) {
  std::error_code error;
  if (!std::filesystem::is_directory(dir, error))
    throw std::runtime_error("the recording folder '" + dir.string() + "' does not exist (or is not a folder)");
  if (k4a::is_site_of_recordings(dir)) return std::make_unique<k4a::SiteRecordings>(dir);
  if (!std::filesystem::exists(dir / "calibration.json", error))
    throw std::runtime_error("'" + dir.string() +
                             "' is not a recording: it has neither a calibration.json (RemoteTouch's format) nor a "
                             "site.json beside one .mkv per camera (k4a recordings)");
  return std::make_unique<sim::ReplayRgbdSource>(dir);
}

std::string recorded_site_kind(const std::filesystem::path& dir) {
  return k4a::is_site_of_recordings(dir) ? "k4a recordings" : "RemoteTouch recording";
}

}  // namespace rt::camera
