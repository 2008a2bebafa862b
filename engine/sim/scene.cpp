#include "sim/scene.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "config/assets.h"
#include "config/json.h"
#include "sim/face.h"

namespace rt::sim {

using namespace config;  // the JSON readers

using config::JsonError;

namespace {

// The site's cameras a scene names, in its order: a scene that needs no more (a clapperboard)
// renders fewer, and each simulated camera costs every frame.
std::vector<RgbdCamera> chosen_cameras(const std::vector<RgbdCamera>& cameras, const nlohmann::json& names,
                                       const std::string& where) {
  if (!names.is_array() || names.empty())
    throw JsonError(where + ": field 'cameras' must be a non-empty list of the site's camera names");
  std::string known;
  for (const RgbdCamera& camera : cameras) known += (known.empty() ? "" : ", ") + camera.name;
  std::vector<RgbdCamera> chosen;
  for (const nlohmann::json& name : names) {
    if (!name.is_string()) throw JsonError(where + ": field 'cameras' must list camera names, has " + name.dump());
    const auto found = std::find_if(cameras.begin(), cameras.end(), [&](const RgbdCamera& c) { return c.name == name; });
    if (found == cameras.end())
      throw JsonError(where + ": field 'cameras': the site has no camera '" + name.get<std::string>() + "' (" + known + ")");
    if (std::any_of(chosen.begin(), chosen.end(), [&](const RgbdCamera& c) { return c.name == name; }))
      throw JsonError(where + ": field 'cameras' names '" + name.get<std::string>() + "' twice");
    chosen.push_back(*found);
  }
  return chosen;
}

MeshDetail mesh_detail_from_json(const nlohmann::json& json, const std::string& where) {
  reject_unknown_fields(json, {"segments", "rings"}, where);
  return {int(require_integer(json, "segments", where, 3, 64)), int(require_integer(json, "rings", where, 1, 32))};
}

SiteSetup site_setup_from_json(const nlohmann::json& json, const std::filesystem::path& base_dir,
                               const std::string& where) {
  reject_unknown_fields(json, {"site", "user", "motion", "cameras"}, where);
  SiteSetup setup;
  const std::string site_name = config::require_string(json, "site", where);
  setup.site_file = (base_dir / site_name).lexically_normal();
  if (!std::filesystem::is_regular_file(setup.site_file))
    throw JsonError(where + ": field 'site': site file '" + setup.site_file.string() + "' does not exist");
  try {
    setup.site = load_site(setup.site_file);
  } catch (const JsonError& error) {
    throw JsonError(where + ": field 'site': " + error.what());
  }
  if (json.contains("cameras")) setup.site.cameras = chosen_cameras(setup.site.cameras, json["cameras"], where);
  setup.user = appearance_from_json(require_object(json, "user", where), where + " user");
  const std::string motion_where = where + " motion";
  setup.motion = motion_from_json(require_object(json, "motion", where), motion_where);
  if (!setup.site.screen.contains(setup.motion.touch_target_m))
    throw JsonError(motion_where + ": field 'touch_target_m' lies outside the screen");
  try {
    [[maybe_unused]] const MotionTrack reachable(setup.motion, setup.site.seat, setup.user);
  } catch (const std::invalid_argument& error) {
    throw JsonError(motion_where + ": field 'touch_target_m': " + error.what());
  }
  return setup;
}

}  // namespace

MotionTrack make_motion_track(const Scene& scene, Site site) {
  const SiteSetup& setup = scene.at(site);
  return MotionTrack(setup.motion, setup.site.seat, setup.user);
}

UserAppearance appearance_from_json(const nlohmann::json& json, const std::string& where) {
  reject_unknown_fields(json, {"skin_rgb", "shirt_rgb", "shirt_stripe_rgb", "stripe_width_m", "hand_scale"}, where);
  UserAppearance user;
  user.skin_rgb = require_rgb(json, "skin_rgb", where);
  user.shirt_rgb = require_rgb(json, "shirt_rgb", where);
  user.shirt_stripe_rgb = require_rgb(json, "shirt_stripe_rgb", where);
  user.stripe_width_m = require_in_range(json, "stripe_width_m", where, 0.002, 0.5);
  // Beyond this the procedural body's proportions stop being human.
  user.hand_scale = require_in_range(json, "hand_scale", where, 0.7, 1.3);
  return user;
}

nlohmann::json appearance_to_json(const UserAppearance& user) {
  return {{"skin_rgb", to_json(user.skin_rgb)},
          {"shirt_rgb", to_json(user.shirt_rgb)},
          {"shirt_stripe_rgb", to_json(user.shirt_stripe_rgb)},
          {"stripe_width_m", user.stripe_width_m},
          {"hand_scale", user.hand_scale}};
}

Scene scene_from_json(const nlohmann::json& json, const std::filesystem::path& base_dir, const std::string& where) {
  reject_unknown_fields(json,
                        {"name", "description", "frames", "fps", "resolution_scale", "color_supersampling", "seed",
                         "viewpoint", "mesh_detail", "sites", "effects"},
                        where);
  Scene scene;
  scene.name = config::require_string(json, "name", where);
  if (json.contains("description")) config::require_string(json, "description", where);
  scene.frame_count = uint32_t(require_integer(json, "frames", where, 1, 1'000'000));
  scene.fps = require_in_range(json, "fps", where, 1.0, 240.0);
  scene.resolution_scale = require_in_range(json, "resolution_scale", where, 0.01, 4.0);
  scene.seed = require_unsigned(json, "seed", where);
  if (json.contains("color_supersampling")) {
    scene.color_supersampling = uint32_t(require_integer(json, "color_supersampling", where, 1, 7));
    if (scene.color_supersampling % 2 == 0)
      throw config::JsonError(where + ": color_supersampling must be odd (1, 3, 5 or 7), got " +
                              std::to_string(scene.color_supersampling));
  }
  if (json.contains("viewpoint")) {
    const std::string viewpoint = config::require_string(json, "viewpoint", where);
    if (viewpoint == "cameras") scene.viewpoint = ViewpointSource::Cameras;
    else if (viewpoint == "seat") scene.viewpoint = ViewpointSource::Seat;
    else throw config::JsonError(where + ": viewpoint must be \"cameras\" or \"seat\", got \"" + viewpoint + "\"");
  }

  if (json.contains("mesh_detail"))
    scene.mesh_detail = mesh_detail_from_json(require_object(json, "mesh_detail", where), where + " mesh_detail");

  const nlohmann::json& sites = require_object(json, "sites", where);
  reject_unknown_fields(sites, {"A", "B"}, where + " sites");
  for (Site site : {Site::A, Site::B}) {
    const std::string name = site_name(site);
    scene.sites[site == Site::A ? 0 : 1] =
        site_setup_from_json(require_object(sites, name, where + " sites"), base_dir, where + " site " + name);
  }

  std::vector<std::string> camera_names;
  for (const SiteSetup& setup : scene.sites)
    for (const RgbdCamera& camera : setup.site.cameras) camera_names.push_back(camera.name);
  if (json.contains("effects")) scene.effects = effects_from_json(json["effects"], where + " effects", camera_names);
  return scene;
}

Eigen::Vector3d truth_viewer_eye(const Scene& scene, Site remote) {
  const Eigen::Vector3d& seat = scene.at(remote).site.seat.head_centre_m;
  return scene.viewpoint == ViewpointSource::Seat ? seat : true_eyes_seated(seat).midpoint();
}

Scene load_scene(const std::filesystem::path& path) {
  const std::string where = "scene '" + path.string() + "'";
  try {
    // read_json_file reports parse errors; a number too large for a double comes as another
    // nlohmann exception, caught here with the rest.
    const nlohmann::json json = config::read_json_file(path);
    return scene_from_json(json, path.parent_path(), where);
  } catch (const nlohmann::json::exception& error) {
    throw JsonError(where + ": " + error.what());
  }
}

}  // namespace rt::sim

namespace rt::sim {

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(config::assets_dir() / "scenes", error))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::filesystem::path resolve_scene(const std::string& scene) {
  const std::filesystem::path given(scene);
  if (given.has_extension() || given.has_parent_path()) return given;
  const std::filesystem::path path = config::assets_dir() / "scenes" / (scene + ".json");
  if (std::filesystem::exists(path)) return path;
  std::string names;
  for (const std::string& name : scene_names()) names += (names.empty() ? "" : ", ") + name;
  throw std::invalid_argument("unknown scene '" + scene + "': the scenes are " + names +
                              " (or give a scene file's path, e.g. my-scene.json)");
}

}  // namespace rt::sim
