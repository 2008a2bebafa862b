#include "sim/effects.h"

#include <algorithm>
#include <functional>

#include "config/json.h"

namespace rt::sim {

using namespace config;  // the JSON readers

using config::JsonError;

namespace {

using Parser = std::function<void(const nlohmann::json&, const std::string&, const std::vector<std::string>&, Effects&)>;

struct EffectParser {
  const char* name;
  Parser parse;
};

const std::vector<EffectParser>& parsers() {
  static const std::vector<EffectParser> table{
      {"depth_noise",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"sigma_at_1m_m", "growth"}, w);
         DepthNoise effect;
         effect.sigma_at_1m_m = require_in_range(j, "sigma_at_1m_m", w, 0.0, 0.5);
         const std::string growth = config::require_string(j, "growth", w);
         if (growth != "quadratic") throw JsonError(w + ": field 'growth' must be \"quadratic\", is \"" + growth + "\"");
         e.depth_noise = effect;
       }},
      {"flying_pixels",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"edge_threshold_m", "probability"}, w);
         e.flying_pixels = FlyingPixels{config::require_positive(j, "edge_threshold_m", w),
                                        require_in_range(j, "probability", w, 0.0, 1.0)};
       }},
      {"near_cutoff",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"min_range_m"}, w);
         e.near_cutoff = NearCutoff{require_in_range(j, "min_range_m", w, 0.0, 10.0)};
       }},
      {"skin_depth_bias",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"bias_m"}, w);
         e.skin_depth_bias = SkinDepthBias{require_in_range(j, "bias_m", w, -0.1, 0.1)};
       }},
      {"color_gain",
       [](const nlohmann::json& j, const std::string& w, const std::vector<std::string>& camera_names, Effects& e) {
         reject_unknown_fields(j, {"cameras"}, w);
         const nlohmann::json& cameras = require_object(j, "cameras", w);
         ColorGain effect;
         for (const auto& [name, entry] : cameras.items()) {
           const std::string cw = w + " camera '" + name + "'";
           if (std::find(camera_names.begin(), camera_names.end(), name) == camera_names.end()) {
             std::string known;
             for (const std::string& n : camera_names) known += (known.empty() ? "" : ", ") + n;
             throw JsonError(w + ": field 'cameras' names unknown camera '" + name + "' (the sites have: " + known + ")");
           }
           reject_unknown_fields(entry, {"gain", "white_balance"}, cw);
           CameraColor color;
           color.gain = require_in_range(entry, "gain", cw, 0.01, 100.0);
           color.white_balance = require_vec3(entry, "white_balance", cw);
           if ((color.white_balance.array() <= 0).any())
             throw JsonError(cw + ": field 'white_balance' must hold three numbers > 0");
           effect.cameras[name] = color;
         }
         e.color_gain = effect;
       }},
      {"misregistration",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"pixels_x", "pixels_y"}, w);
         e.misregistration = Misregistration{require_in_range(j, "pixels_x", w, -100.0, 100.0),
                                             require_in_range(j, "pixels_y", w, -100.0, 100.0)};
       }},
      {"camera_timing_jitter",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"sigma_ms"}, w);
         e.camera_timing_jitter = CameraTimingJitter{require_in_range(j, "sigma_ms", w, 0.0, 1000.0)};
       }},
      {"tracker_jitter",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"sigma_mm"}, w);
         e.tracker.jitter = TrackerJitter{require_in_range(j, "sigma_mm", w, 0.0, 100.0)};
       }},
      {"tracker_latency",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"ms"}, w);
         e.tracker.latency = TrackerLatency{require_in_range(j, "ms", w, 0.0, 2000.0)};
       }},
      {"tracker_dropouts",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"probability", "mean_length_frames"}, w);
         // A lost fraction of 1 would mean the hand is never seen again.
         const TrackerDropouts dropouts{require_in_range(j, "probability", w, 0.0, 0.95),
                                        require_in_range(j, "mean_length_frames", w, 1.0, 10000.0)};
         // Bursts of mean length m can cover at most m / (m + 1) of the frames.
         const double most = dropouts.mean_length_frames / (dropouts.mean_length_frames + 1.0);
         if (dropouts.probability > most)
           throw JsonError(w + ": field 'probability' " + format_number(dropouts.probability) +
                           " cannot be reached with bursts of " + format_number(dropouts.mean_length_frames) +
                           " frames (at most " + format_number(most) + "); make 'mean_length_frames' longer");
         e.tracker.dropouts = dropouts;
       }},
      {"room_echo",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"delay_ms", "gain_db", "reverb_ms", "reverb_db"}, w);
         e.room_echo = RoomEcho{require_in_range(j, "delay_ms", w, 10.0, 500.0), require_in_range(j, "gain_db", w, -60.0, 0.0),
                                require_in_range(j, "reverb_ms", w, 0.0, 1000.0), require_in_range(j, "reverb_db", w, -80.0, 0.0)};
       }},
      {"av_marker",
       [](const nlohmann::json& j, const std::string& w, const auto&, Effects& e) {
         reject_unknown_fields(j, {"times_s", "flash_ms"}, w);
         AvMarker marker;
         marker.flash_ms = require_in_range(j, "flash_ms", w, 10.0, 2000.0);
         const nlohmann::json& times = require_array(j, "times_s", w, 1, 64);
         for (size_t i = 0; i < times.size(); ++i) {
           const std::string at = w + ": times_s[" + std::to_string(i) + "]";
           if (!times[i].is_number() || !(times[i].get<double>() >= 0.0 && times[i].get<double>() <= 3600.0))
             throw JsonError(at + " must be a time in seconds within [0, 3600], is " + times[i].dump());
           marker.times_s.push_back(times[i].get<double>());
         }
         std::sort(marker.times_s.begin(), marker.times_s.end());
         // Apart by more than a flash, so that each flash and each click is told from the next.
         for (size_t i = 1; i < marker.times_s.size(); ++i)
           if (marker.times_s[i] - marker.times_s[i - 1] < 2.0 * marker.flash_ms / 1000.0)
             throw JsonError(w + ": times_s " + format_number(marker.times_s[i - 1]) + " and " +
                             format_number(marker.times_s[i]) + " are closer than two flashes (" +
                             format_number(2.0 * marker.flash_ms) + " ms)");
         e.av_marker = marker;
       }},
  };
  return table;
}

}  // namespace

bool AvMarker::flashing_at(double t_s) const {
  // The first marker after t, then the one before it: the times are sorted.
  const auto after = std::upper_bound(times_s.begin(), times_s.end(), t_s);
  return after != times_s.begin() && t_s < *std::prev(after) + flash_ms / 1000.0;
}

CameraColor ColorGain::for_camera(const std::string& name) const {
  const auto it = cameras.find(name);
  return it == cameras.end() ? CameraColor{} : it->second;
}

bool Effects::any() const {
  return depth_noise || flying_pixels || near_cutoff || skin_depth_bias || color_gain || misregistration ||
         camera_timing_jitter || tracker.jitter || tracker.latency || tracker.dropouts || room_echo || av_marker;
}

const std::vector<std::string>& effect_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const EffectParser& parser : parsers()) all.push_back(parser.name);
    return all;
  }();
  return names;
}

Effects effects_from_json(const nlohmann::json& json, const std::string& where,
                          const std::vector<std::string>& camera_names) {
  if (!json.is_object()) throw JsonError(where + ": must be an object of effect names to parameters");
  Effects effects;
  for (const auto& [name, parameters] : json.items()) {
    const auto parser = std::find_if(parsers().begin(), parsers().end(),
                                     [&name = name](const EffectParser& p) { return name == p.name; });
    if (parser == parsers().end()) {
      std::string known;
      for (const std::string& n : effect_names()) known += (known.empty() ? "" : ", ") + n;
      throw JsonError(where + ": unknown effect '" + name + "' (known: " + known + ")");
    }
    const std::string effect_where = where + " '" + name + "'";
    if (!parameters.is_object())
      throw JsonError(effect_where + ": parameters must be an object, not " + std::string(parameters.type_name()));
    parser->parse(parameters, effect_where, camera_names, effects);
  }
  return effects;
}

nlohmann::json effects_to_json(const Effects& e) {
  nlohmann::json json = nlohmann::json::object();
  if (e.depth_noise) json["depth_noise"] = {{"sigma_at_1m_m", e.depth_noise->sigma_at_1m_m}, {"growth", "quadratic"}};
  if (e.flying_pixels)
    json["flying_pixels"] = {{"edge_threshold_m", e.flying_pixels->edge_threshold_m},
                             {"probability", e.flying_pixels->probability}};
  if (e.near_cutoff) json["near_cutoff"] = {{"min_range_m", e.near_cutoff->min_range_m}};
  if (e.skin_depth_bias) json["skin_depth_bias"] = {{"bias_m", e.skin_depth_bias->bias_m}};
  if (e.color_gain) {
    nlohmann::json cameras = nlohmann::json::object();
    for (const auto& [name, color] : e.color_gain->cameras)
      cameras[name] = {{"gain", color.gain}, {"white_balance", to_json(color.white_balance)}};
    json["color_gain"] = {{"cameras", cameras}};
  }
  if (e.misregistration)
    json["misregistration"] = {{"pixels_x", e.misregistration->pixels_x}, {"pixels_y", e.misregistration->pixels_y}};
  if (e.camera_timing_jitter) json["camera_timing_jitter"] = {{"sigma_ms", e.camera_timing_jitter->sigma_ms}};
  if (e.tracker.jitter) json["tracker_jitter"] = {{"sigma_mm", e.tracker.jitter->sigma_mm}};
  if (e.tracker.latency) json["tracker_latency"] = {{"ms", e.tracker.latency->ms}};
  if (e.tracker.dropouts)
    json["tracker_dropouts"] = {{"probability", e.tracker.dropouts->probability},
                                {"mean_length_frames", e.tracker.dropouts->mean_length_frames}};
  if (e.room_echo)
    json["room_echo"] = {{"delay_ms", e.room_echo->delay_ms},
                         {"gain_db", e.room_echo->gain_db},
                         {"reverb_ms", e.room_echo->reverb_ms},
                         {"reverb_db", e.room_echo->reverb_db}};
  if (e.av_marker) json["av_marker"] = {{"times_s", e.av_marker->times_s}, {"flash_ms", e.av_marker->flash_ms}};
  return json;
}

}  // namespace rt::sim
