// `remotetouch site --config FILE`: the JSON fields that set a site's options.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"
#include "config/json.h"
#include "site/site_options.h"

#include "audio/audio_spec.h"
#include "tracker/leap_url.h"

namespace rt::site {

std::optional<std::string> leap_tracker_url(const std::string& tracker) {
  if (tracker == "scene") return std::nullopt;
  if (tracker == "leap") return std::string(devices::kDefaultLeapUrl);
  if (tracker.rfind("leap:", 0) == 0) {
    devices::parse_leap_url(tracker.substr(5));
    return tracker.substr(5);
  }
  throw std::invalid_argument("'" + tracker + "' is not a tracker: scene, leap, or leap:ws://HOST:PORT/PATH");
}

DisplayMode parse_display_mode(const std::string& display, bool display_present) {
  if (display == "window") return DisplayMode::Window;
  if (display == "headless") return DisplayMode::Headless;
  if (display == "both") return DisplayMode::Both;
  if (display == "auto") return display_present ? DisplayMode::Window : DisplayMode::Headless;
  throw std::invalid_argument("'" + display + "' is not a display: window, headless, both or auto");
}

bool display_present() {
  for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY"})
    if (const char* value = std::getenv(name); value && *value) return true;
  return false;
}

void apply_site_config(const std::filesystem::path& config, SiteRunOptions& options) {
  const nlohmann::json json = config::read_json_file(config);
  if (!json.is_object()) throw std::runtime_error(config.string() + ": not a JSON object");
  const std::filesystem::path base = config.parent_path();
  auto string_field = [&](const char* name, std::string& value) {
    if (!json.contains(name)) return;
    if (!json[name].is_string()) throw std::runtime_error(config.string() + ": '" + name + "' must be a string");
    value = json[name].get<std::string>();
  };
  auto number_field = [&](const char* name, auto& value, double min, double max) {
    if (!json.contains(name)) return;
    if (!json[name].is_number() || json[name].get<double>() < min || json[name].get<double>() > max)
      throw std::runtime_error(config.string() + ": '" + name + "' must be a number in [" + std::to_string(min) + ", " +
                               std::to_string(max) + "]");
    value = static_cast<std::remove_reference_t<decltype(value)>>(json[name].get<double>());
  };
  // A file the config names, relative to the config's folder unless absolute; left as it was when absent.
  auto path_field = [&](const char* name, std::filesystem::path& value) {
    std::string path;
    string_field(name, path);
    if (!path.empty()) value = std::filesystem::path(path).is_absolute() ? std::filesystem::path(path) : (base / path).lexically_normal();
  };
  for (const auto& [key, value] : json.items())
    if (key != "scene" && key != "site" && key != "listen" && key != "peer" && key != "key_file" && key != "transport" && key != "stun" && key != "turn" && key != "relay_only" &&
        key != "bitrate_floor_kbps" && key != "bitrate_ceiling_kbps" && key != "janus" && key != "room" && key != "room_secret" && key != "janus_ca" &&
        key != "time_scale" &&
        key != "resolution_scale" && key != "width" && key != "height" && key != "frames" && key != "replay" && key != "site_file" &&
        key != "motor" &&  key != "tracker" && key != "display" && key != "monitor" &&
        key != "present_mode" && key != "ibr" && key != "hand" && key != "touch" && key != "audio_in" && key != "audio_out")
      throw std::runtime_error(config.string() + ": unknown field '" + key + "'");
  std::string site = site_name(options.site);
  string_field("scene", options.scene);
  string_field("site", site);
  if (site != "A" && site != "B") throw std::runtime_error(config.string() + ": 'site' must be \"A\" or \"B\"");
  options.site = site == "A" ? Site::A : Site::B;
  string_field("listen", options.listen);
  string_field("peer", options.peer);
  path_field("key_file", options.key_file);
  string_field("transport", options.transport);
  string_field("stun", options.call.stun);
  string_field("turn", options.call.turn);
  if (json.contains("relay_only")) {
    if (!json["relay_only"].is_boolean()) throw std::runtime_error(config.string() + ": 'relay_only' must be true or false");
    options.call.relay_only = json["relay_only"].get<bool>();
  }
  number_field("bitrate_floor_kbps", options.call.bitrate_floor_kbps, 50, 100000);
  number_field("bitrate_ceiling_kbps", options.call.bitrate_ceiling_kbps, 50, 100000);
  string_field("janus", options.call.janus);
  if (json.contains("room") && (!json["room"].is_number_unsigned() || json["room"].get<uint64_t>() == 0))
    throw std::runtime_error(config.string() + ": 'room' must be a whole number above 0 (the Janus room's)");
  if (json.contains("room")) options.call.room = json["room"].get<uint64_t>();
  path_field("room_secret", options.call.room_secret_file);
  path_field("janus_ca", options.call.janus_ca_file);
  if (options.transport != "direct" && options.transport != "webrtc")
    throw std::runtime_error(config.string() + ": 'transport' must be \"direct\" or \"webrtc\"");
  path_field("replay", options.replay);
  path_field("site_file", options.site_file);
  string_field("motor", options.motor);
  string_field("tracker", options.tracker);
  try {
    leap_tracker_url(options.tracker);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(config.string() + ": 'tracker': " + error.what());
  }
  if (options.motor != "simulated" && options.motor != "usb" && options.motor != "auto")
    throw std::runtime_error(config.string() + ": 'motor' must be \"simulated\", \"usb\" or \"auto\"");
  string_field("audio_in", options.sound.audio_in);
  string_field("audio_out", options.sound.audio_out);
  for (auto [name, value] : {std::pair{"audio_in", &options.sound.audio_in}, {"audio_out", &options.sound.audio_out}}) {
    try {
      audio::parse_audio_spec(*value, name);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(config.string() + ": '" + name + "': " + error.what());
    }
  }
  string_field("display", options.display);
  string_field("present_mode", options.present_mode);
  try {
    parse_display_mode(options.display, false);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(config.string() + ": 'display': " + error.what());
  }
  if (options.present_mode != "fifo" && options.present_mode != "mailbox")
    throw std::runtime_error(config.string() + ": 'present_mode' must be \"fifo\" or \"mailbox\"");
  number_field("monitor", options.monitor, -1, 64);
  number_field("time_scale", options.time_scale, 1e-3, 10.0);
  number_field("resolution_scale", options.resolution_scale, 0.0, 1.0);
  number_field("width", options.run.width, 16, 4096);
  number_field("height", options.run.height, 16, 4096);
  // The image-based model's and the hand's knobs, keys as their options with '_' for '-'.
  if (json.contains("ibr")) config::read_knobs_json(pipeline::ibr_knobs(), json["ibr"], options.ibr, config.string() + ": 'ibr'");
  if (json.contains("hand"))
    config::read_knobs_json(pipeline::hand_knobs(), json["hand"], options.hand, config.string() + ": 'hand'");
  if (json.contains("touch"))
    config::read_knobs_json(touch_knobs(), json["touch"], options.touch, config.string() + ": 'touch'");
  if (json.contains("frames")) {
    number_field("frames", options.run.frames, 1, 1e6);
    options.frames_given = true;
  }
}

}  // namespace rt::site
