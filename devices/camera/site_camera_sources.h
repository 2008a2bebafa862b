#pragma once
// Where each camera of a site file takes its frames from: "simulated" (the simulator), "k4a" (a
// live device, by serial, with its modes and wired-sync role in the camera's "k4a" object) or
// "k4a-recording:PATH" (a recording of one; a relative path is from the site file's folder).
// One site runs its cameras from one kind of source: a mix (a live camera beside a recording)
// is refused, naming the cameras of each kind.
#include <filesystem>
#include <string>
#include <vector>

#include "camera/k4a_live_camera.h"
#include "sim/site_description.h"

namespace rt::camera {

enum class CameraSourceKind { simulated, k4a_live, k4a_recording };
std::string_view camera_source_kind_name(CameraSourceKind kind);

struct CameraSource {
  CameraSourceKind kind = CameraSourceKind::simulated;
  std::filesystem::path recording;   // k4a_recording
  k4a::LiveCameraSettings live;      // k4a_live
};

// Per camera, in the site's order. `site_dir` resolves relative recording paths. Throws
// config::JsonError naming `where`, the camera and the field.
std::vector<CameraSource> camera_sources(const sim::SiteDescription& site, const std::filesystem::path& site_dir,
                                         const std::string& where);
// The kind all the cameras share; throws config::JsonError listing them when they differ.
CameraSourceKind site_source_kind(const sim::SiteDescription& site, const std::string& where);

// Every camera's device settings, when all are live; throws config::JsonError naming `where`
// and the cameras that are not.
std::vector<k4a::LiveCameraSettings> live_site_settings(const sim::SiteDescription& site, const std::string& where);

// The colour lens a real camera (live or recorded) is used with: `factory`, its device's
// calibration at the recorded mode, unless the site file says "color_lens": "site-file", when
// the site file's colour intrinsics are used. Throws config::JsonError naming `where` and the
// camera when those are for another image size than the device's.
CameraIntrinsics color_lens_for(const sim::RgbdCamera& described, const CameraIntrinsics& factory,
                                const std::string& where);

// A live camera's "k4a" object: "serial" (required), "color_mode" ("MJPG_720P"), "depth_mode"
// ("NFOV_UNBINNED"), "fps" (30), "wired_sync" ("STANDALONE", "MASTER", "SUBORDINATE"),
// "subordinate_delay_us" (0), "depth_delay_us" (0); defaults in brackets.
k4a::LiveCameraSettings live_settings_from_json(const nlohmann::json& settings, const std::string& where);

}  // namespace rt::camera
