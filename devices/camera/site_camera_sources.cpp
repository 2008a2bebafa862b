#include "camera/site_camera_sources.h"

#include "config/json.h"

namespace rt::camera {

using config::JsonError;

std::string_view camera_source_kind_name(CameraSourceKind kind) {
  switch (kind) {
    case CameraSourceKind::simulated: return "simulated";
    case CameraSourceKind::k4a_live: return "k4a (live)";
    case CameraSourceKind::k4a_recording: return "k4a-recording";
  }
  return "unknown";
}

k4a::LiveCameraSettings live_settings_from_json(const nlohmann::json& json, const std::string& where) {
  using namespace k4a;
  config::reject_unknown_fields(
      json, {"serial", "color_mode", "depth_mode", "fps", "wired_sync", "subordinate_delay_us", "depth_delay_us"}, where);
  LiveCameraSettings settings;
  settings.serial = config::require_string(json, "serial", where);
  if (settings.serial.empty()) throw JsonError(where + ": \"serial\" is empty (`remotetouch list-cameras` shows them)");
  if (json.contains("color_mode")) {
    const std::string tag = config::require_string(json, "color_mode", where);
    const std::optional<ColorMode> mode = color_mode_from_tag(tag);
    if (!mode) throw JsonError(where + ": \"color_mode\" '" + tag + "' is not a k4a colour mode (e.g. MJPG_720P, BGRA_1080P)");
    settings.color_format = mode->format;
    settings.color_resolution = mode->resolution;
  }
  if (json.contains("depth_mode")) {
    const std::string name = config::require_string(json, "depth_mode", where);
    const std::optional<DepthMode> mode = depth_mode_from_name(name);
    if (!mode)
      throw JsonError(where + ": \"depth_mode\" '" + name +
                      "' is none of NFOV_2X2BINNED, NFOV_UNBINNED, WFOV_2X2BINNED, WFOV_UNBINNED");
    settings.depth_mode = *mode;
  }
  if (json.contains("fps")) {
    settings.fps = uint32_t(config::require_integer(json, "fps", where, 0, 1000));
    if (!is_frame_rate(settings.fps)) throw JsonError(where + ": \"fps\" must be 5, 15 or 30");
  }
  if (settings.fps > 15 &&
      (settings.depth_mode == DepthMode::wfov_unbinned || settings.color_resolution == ColorResolution::p3072))
    throw JsonError(where + ": WFOV_UNBINNED depth and 3072P colour run at 15 fps at most (set \"fps\": 15)");
  if (json.contains("wired_sync")) {
    const std::string name = config::require_string(json, "wired_sync", where);
    if (name == "STANDALONE") settings.wired_sync = WiredSyncMode::standalone;
    else if (name == "MASTER") settings.wired_sync = WiredSyncMode::master;
    else if (name == "SUBORDINATE") settings.wired_sync = WiredSyncMode::subordinate;
    else throw JsonError(where + ": \"wired_sync\" '" + name + "' is none of STANDALONE, MASTER, SUBORDINATE");
  }
  // A frame period at 5 fps bounds both delays: more would put a capture in another frame.
  if (json.contains("subordinate_delay_us"))
    settings.subordinate_delay_us = uint32_t(config::require_integer(json, "subordinate_delay_us", where, 0, 200'000));
  if (settings.subordinate_delay_us != 0 && settings.wired_sync != WiredSyncMode::subordinate)
    throw JsonError(where + ": \"subordinate_delay_us\" is for a SUBORDINATE only");
  if (json.contains("depth_delay_us"))
    settings.depth_delay_us = int32_t(config::require_integer(json, "depth_delay_us", where, -200'000, 200'000));
  return settings;
}

std::vector<CameraSource> camera_sources(const sim::SiteDescription& site, const std::filesystem::path& site_dir,
                                         const std::string& where) {
  constexpr std::string_view kRecording = "k4a-recording:";
  std::vector<CameraSource> sources;
  for (const sim::RgbdCamera& camera : site.cameras) {
    const std::string camera_where = where + " (camera '" + camera.name + "')";
    CameraSource source;
    if (camera.source == "k4a") {
      source.kind = CameraSourceKind::k4a_live;
      source.live = live_settings_from_json(camera.k4a, camera_where + " k4a");
    } else if (camera.source.starts_with(kRecording)) {
      source.kind = CameraSourceKind::k4a_recording;
      source.recording = std::filesystem::path(camera.source.substr(kRecording.size()));
      if (source.recording.is_relative()) source.recording = site_dir / source.recording;
    } else if (camera.source != "simulated") {
      throw JsonError(camera_where + ": unknown source '" + camera.source + "'");
    }
    sources.push_back(std::move(source));
  }
  return sources;
}

CameraSourceKind site_source_kind(const sim::SiteDescription& site, const std::string& where) {
  const std::vector<CameraSource> sources = camera_sources(site, ".", where);
  if (sources.empty()) return CameraSourceKind::simulated;
  const CameraSourceKind kind = sources.front().kind;
  for (const CameraSource& source : sources) {
    if (source.kind == kind) continue;
    std::string list;
    for (size_t k = 0; k < sources.size(); ++k)
      list += (k ? ", '" : "'") + site.cameras[k].name + "' " + std::string(camera_source_kind_name(sources[k].kind));
    throw JsonError(where + ": the cameras' sources are mixed (" + list +
                    "); a site runs all its cameras from one kind of source: all live (\"k4a\"), all recorded "
                    "(\"k4a-recording:PATH\") or all simulated");
  }
  return kind;
}

std::vector<k4a::LiveCameraSettings> live_site_settings(const sim::SiteDescription& site, const std::string& where) {
  if (site.cameras.empty()) throw JsonError(where + " lists no cameras");
  std::vector<k4a::LiveCameraSettings> settings;
  std::string not_live;
  const std::vector<CameraSource> sources = camera_sources(site, ".", where);
  for (size_t k = 0; k < sources.size(); ++k) {
    if (sources[k].kind == CameraSourceKind::k4a_live) settings.push_back(sources[k].live);
    else not_live += (not_live.empty() ? "'" : ", '") + site.cameras[k].name + "' (" + site.cameras[k].source + ")";
  }
  if (!not_live.empty())
    throw JsonError(where + ": live cameras need every camera's source to be \"k4a\" with its \"k4a\" settings; " +
                    not_live + (not_live.find(',') == std::string::npos ? " is" : " are") + " not live");
  return settings;
}

CameraIntrinsics color_lens_for(const sim::RgbdCamera& described, const CameraIntrinsics& factory,
                                const std::string& where) {
  if (!described.color_lens_from_site_file) return factory;
  if (described.color.width != factory.width || described.color.height != factory.height)
    throw JsonError(where + ": camera '" + described.name + "' takes its colour lens from the site file (\"color_lens\": " +
                    "\"site-file\"), which is for " + std::to_string(described.color.width) + "x" +
                    std::to_string(described.color.height) + "; its device records " + std::to_string(factory.width) +
                    "x" + std::to_string(factory.height));
  return described.color;
}

}  // namespace rt::camera
