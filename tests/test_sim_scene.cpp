// Scenes: the shipped ones load and do what their names say (clap touches one spot of the shared
// glass from both sides, miss does not); bad scene files are refused, naming the field and file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "config/assets.h"
#include "config/json.h"
#include "geometry/site_frames.h"
#include "sim/motion.h"
#include "sim/scene.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::sim;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kScenesSimScene = rt::config::assets_dir() / "scenes";
const char* const kShippedScenes[] = {"clap", "miss", "wave", "approach", "noisy-clap", "train-fast-reach", "train-raise-hold",
                                      "av-marker"};

struct Touch {
  Eigen::Vector3d palm_global = Eigen::Vector3d::Zero();
  double start_s = -1, end_s = -1;  // while the palm is within 1 cm of the glass
};

// Where and when the right palm of `site`'s user rests on the glass, in the global frame.
Touch find_touch(const Scene& scene, Site site) {
  const SiteSetup& setup = scene.at(site);
  const MotionTrack track(setup.motion, setup.site.seat, setup.user);
  Touch touch;
  for (uint32_t frame = 0; frame < scene.frame_count; ++frame) {
    const double t = frame / scene.fps;
    const Eigen::Vector3d palm = track.pose_at(t).right_hand.palm;
    if (palm.z() >= 0.01) continue;
    if (touch.start_s < 0) touch.start_s = t;
    touch.end_s = t;
    touch.palm_global = global_from_site(site) * palm;
  }
  return touch;
}

nlohmann::json clap_json() { return config::read_json_file(kScenesSimScene / "clap.json"); }

void require_error(const nlohmann::json& json, const std::string& part1, const std::string& part2 = "") {
  try {
    scene_from_json(json, kScenesSimScene, "scene 'test.json'");
    FAIL("accepted a bad scene");
  } catch (const config::JsonError& error) {
    CHECK_THAT(error.what(), Contains("scene 'test.json'") && Contains(part1) && Contains(part2));
  }
}

}  // namespace

TEST_CASE("the shipped scenes load; two different users; motions fit in the frames", "[sim][scene]") {
  for (const char* name : kShippedScenes) {
    INFO(name);
    const Scene scene = load_scene(kScenesSimScene / (std::string(name) + ".json"));
    CHECK(scene.name == name);
    CHECK(scene.fps == 30.0);
    CHECK(scene.frame_count >= 60);
    CHECK(scene.resolution_scale > 0.0);
    const SiteSetup& a = scene.at(Site::A);
    const SiteSetup& b = scene.at(Site::B);
    // The clapperboard renders two cameras (its picture needs no more; each costs every frame).
    CHECK(a.site.cameras.size() == (std::string(name) == "av-marker" ? 2 : 6));
    CHECK(a.site_file.filename() == "default.json");
    CHECK(a.user.hand_scale != b.user.hand_scale);
    CHECK((a.user.skin_rgb - b.user.skin_rgb).norm() > 0.2);
    for (Site site : {Site::A, Site::B}) {
      const SiteSetup& setup = scene.at(site);
      CHECK(make_motion_track(scene, site).duration_s() <= scene.duration_s());  // no motion cut short
      // A touch lands where the site's tracker is known to see it.
      const Eigen::Vector2d offset = setup.motion.touch_target_m - setup.site.touch_region.centre_m;
      if (setup.motion.kind != MotionKind::Idle && setup.motion.kind != MotionKind::Wave)
        CHECK((offset.cwiseAbs().array() <= setup.site.touch_region.half_size_m.array()).all());
    }
  }
}

TEST_CASE("clap: both palms meet on one spot of the shared glass, at the same time", "[sim][scene]") {
  const Scene scene = load_scene(kScenesSimScene / "clap.json");
  const Touch a = find_touch(scene, Site::A), b = find_touch(scene, Site::B);
  REQUIRE(a.start_s >= 0);
  REQUIRE(b.start_s >= 0);
  CHECK((a.palm_global - b.palm_global).head<2>().norm() < 0.02);
  CHECK(std::min(a.end_s, b.end_s) - std::max(a.start_s, b.start_s) > 0.5);  // both on the glass for 0.5 s
  // The palms face each other through the glass.
  CHECK(a.palm_global.z() > 0);
  CHECK(b.palm_global.z() < 0);
}

TEST_CASE("the cameras keep the head (top row) and the chest (all) in view while the user leans in to touch",
          "[sim][scene]") {
  const Scene scene = load_scene(kScenesSimScene / "clap.json");
  for (Site site : {Site::A, Site::B}) {
    const MotionTrack track = make_motion_track(scene, site);
    for (uint32_t frame = 0; frame < scene.frame_count; frame += 3) {
      const PersonPose pose = track.pose_at(frame / scene.fps);
      for (const RgbdCamera& camera : scene.at(site).site.cameras) {
        INFO("site " << site_name(site) << " frame " << frame << " camera " << camera.name);
        if (camera.color_camera().position_in_site().y() > 0) CHECK(camera.why_unseen(pose.head_centre) == "");
        CHECK(camera.why_unseen(pose.head_centre - Eigen::Vector3d(0, 0.3, 0)) == "");
      }
    }
  }
}

TEST_CASE("miss: both touch the glass at the same time, far apart", "[sim][scene]") {
  const Scene scene = load_scene(kScenesSimScene / "miss.json");
  const Touch a = find_touch(scene, Site::A), b = find_touch(scene, Site::B);
  REQUIRE(a.start_s >= 0);
  REQUIRE(b.start_s >= 0);
  CHECK((a.palm_global - b.palm_global).head<2>().norm() > 0.3);
  CHECK(std::min(a.end_s, b.end_s) - std::max(a.start_s, b.start_s) > 0.5);
}

TEST_CASE("effects are off unless listed; noisy-clap lists them all with their parameters", "[sim][scene]") {
  for (const char* name : {"clap", "miss", "wave", "approach"})
    CHECK_FALSE(load_scene(kScenesSimScene / (std::string(name) + ".json")).effects.any());
  const Effects effects = load_scene(kScenesSimScene / "noisy-clap.json").effects;
  REQUIRE(effects.depth_noise);
  CHECK(effects.depth_noise->sigma_at_1m_m == 0.003);
  REQUIRE(effects.flying_pixels);
  CHECK(effects.flying_pixels->edge_threshold_m == 0.05);
  REQUIRE(effects.near_cutoff);
  CHECK(effects.near_cutoff->min_range_m == 0.25);
  REQUIRE(effects.skin_depth_bias);
  CHECK(effects.skin_depth_bias->bias_m == 0.01);
  REQUIRE(effects.color_gain);
  CHECK(effects.color_gain->for_camera("top-left").gain == 1.15);
  CHECK(effects.color_gain->for_camera("top-left").white_balance == Eigen::Vector3d(1.05, 1.0, 0.92));
  CHECK(effects.color_gain->for_camera("bottom-left").gain == 1.0);  // not listed: unchanged
  REQUIRE(effects.misregistration);
  CHECK(effects.misregistration->pixels_y == -1.0);
  REQUIRE(effects.camera_timing_jitter);
  CHECK(effects.camera_timing_jitter->sigma_ms == 3.0);
  REQUIRE(effects.tracker.jitter);
  CHECK(effects.tracker.jitter->sigma_mm == 1.5);
  REQUIRE(effects.tracker.latency);
  CHECK(effects.tracker.latency->ms == 30.0);
  REQUIRE(effects.tracker.dropouts);
  CHECK(effects.tracker.dropouts->mean_length_frames == 4.0);
  // Written back, the effects read the same.
  const Effects again = effects_from_json(effects_to_json(effects), "again", {"top-left", "top-centre", "bottom-right"});
  CHECK(effects_to_json(again) == effects_to_json(effects));
}

TEST_CASE("av-marker: each flash lasts its flash_ms from its time, the markers read back the same", "[sim][scene]") {
  const Effects effects = load_scene(kScenesSimScene / "av-marker.json").effects;
  REQUIRE(effects.av_marker);
  const AvMarker& marker = *effects.av_marker;
  REQUIRE(marker.times_s == std::vector<double>{1.0, 2.1, 3.2});
  CHECK_FALSE(marker.flashing_at(0.0));
  CHECK_FALSE(marker.flashing_at(0.9999));
  CHECK(marker.flashing_at(30.0 / 30.0));  // the frame at the marker's time flashes
  CHECK(marker.flashing_at(1.0 + marker.flash_ms / 1000.0 - 1e-6));
  CHECK_FALSE(marker.flashing_at(1.0 + marker.flash_ms / 1000.0));
  CHECK_FALSE(marker.flashing_at(2.0));
  CHECK(marker.flashing_at(63.0 / 30.0));
  CHECK(marker.flashing_at(3.3));
  CHECK_FALSE(marker.flashing_at(100.0));
  // Cheap to simulate, so that a CPU renderer shows every frame: two cameras, coarse capsules.
  const Scene scene = load_scene(kScenesSimScene / "av-marker.json");
  const SiteDescription full = load_site(scene.at(Site::A).site_file);
  for (Site site : {Site::A, Site::B}) {
    const std::vector<RgbdCamera>& cameras = scene.at(site).site.cameras;
    REQUIRE(cameras.size() == 2);
    CHECK(cameras[0].name == "top-centre");
    CHECK(cameras[1].name == "bottom-centre");
    // Each is the site file's camera of that name, its calibration untouched.
    for (const RgbdCamera& camera : cameras) {
      const auto same = std::find_if(full.cameras.begin(), full.cameras.end(), [&](const RgbdCamera& c) { return c.name == camera.name; });
      REQUIRE(same != full.cameras.end());
      CHECK(camera.camera_from_site.isApprox(same->camera_from_site));
      CHECK(camera.color.fx == same->color.fx);
    }
  }
  CHECK(scene.mesh_detail.segments == 6);
  CHECK(scene.mesh_detail.rings == 2);
  CHECK(load_scene(kScenesSimScene / "clap.json").mesh_detail.segments == 16);
  // Nothing else: a marker scene asks for no other imperfection.
  CHECK_FALSE(effects.room_echo);
  CHECK_FALSE(effects.depth_noise);
  const Effects again = effects_from_json(effects_to_json(effects), "again", {});
  CHECK(effects_to_json(again) == effects_to_json(effects));
}

TEST_CASE("bad scenes name the field", "[sim][scene]") {
  SECTION("a camera the site does not have, or named twice, or none") {
    nlohmann::json json = clap_json();
    json["sites"]["A"]["cameras"] = {"top-centre", "middle"};
    require_error(json, "site A", "no camera 'middle' (top-left, top-centre");
    json["sites"]["A"]["cameras"] = {"top-centre", "top-centre"};
    require_error(json, "site A", "names 'top-centre' twice");
    json["sites"]["A"]["cameras"] = nlohmann::json::array();
    require_error(json, "site A", "'cameras' must be a non-empty list");
    json["sites"]["A"]["cameras"] = {"top-centre", 3};
    require_error(json, "site A", "'cameras' must list camera names");
  }
  SECTION("a mesh detail out of range or misspelt") {
    nlohmann::json json = clap_json();
    json["mesh_detail"] = {{"segments", 2}, {"rings", 2}};
    require_error(json, "mesh_detail", "'segments' must be in [3, 64]");
    json["mesh_detail"] = {{"segments", 6}, {"ring", 2}};
    require_error(json, "mesh_detail", "unknown field 'ring'");
  }
  SECTION("missing frame count") {
    nlohmann::json json = clap_json();
    json.erase("frames");
    require_error(json, "missing field 'frames'");
  }
  SECTION("fps of the wrong type") {
    nlohmann::json json = clap_json();
    json["fps"] = "thirty";
    require_error(json, "'fps' must be a number");
  }
  SECTION("fractional frame count") {
    nlohmann::json json = clap_json();
    json["frames"] = 12.5;
    require_error(json, "'frames' must be an integer");
  }
  SECTION("negative seed") {
    nlohmann::json json = clap_json();
    json["seed"] = -3;
    require_error(json, "'seed' must not be negative");
  }
  SECTION("unknown effect") {
    nlohmann::json json = clap_json();
    json["effects"]["motion_blur"] = {{"pixels", 3}};
    require_error(json, "unknown effect 'motion_blur'", "tracker_dropouts");
  }
  SECTION("effect parameter missing") {
    nlohmann::json json = clap_json();
    json["effects"]["tracker_jitter"] = nlohmann::json::object();
    require_error(json, "'tracker_jitter'", "missing field 'sigma_mm'");
  }
  SECTION("effect parameter misspelt") {
    nlohmann::json json = clap_json();
    json["effects"]["tracker_latency"] = {{"ms", 20}, {"jitter_ms", 2}};
    require_error(json, "'tracker_latency'", "unknown field 'jitter_ms'");
  }
  SECTION("effect parameter out of range") {
    nlohmann::json json = clap_json();
    json["effects"]["flying_pixels"] = {{"edge_threshold_m", 0.05}, {"probability", 1.5}};
    require_error(json, "'flying_pixels'", "'probability' must be in [0, 1], is 1.5");
  }
  SECTION("depth noise growth that is not quadratic") {
    nlohmann::json json = clap_json();
    json["effects"]["depth_noise"] = {{"sigma_at_1m_m", 0.002}, {"growth", "linear"}};
    require_error(json, "'depth_noise'", "'growth'");
  }
  SECTION("dropouts that no burst length can give") {
    nlohmann::json json = clap_json();
    json["effects"]["tracker_dropouts"] = {{"probability", 0.9}, {"mean_length_frames", 2}};
    require_error(json, "'tracker_dropouts'", "'mean_length_frames' longer");
  }
  SECTION("a marker time that is not a time") {
    nlohmann::json json = clap_json();
    json["effects"]["av_marker"] = {{"times_s", {1.0, "soon"}}, {"flash_ms", 200}};
    require_error(json, "'av_marker'", "times_s[1] must be a time in seconds within [0, 3600], is \"soon\"");
    json["effects"]["av_marker"] = {{"times_s", {-1.0}}, {"flash_ms", 200}};
    require_error(json, "'av_marker'", "times_s[0] must be a time in seconds");
  }
  SECTION("markers too close to be told apart, none, or too many") {
    nlohmann::json json = clap_json();
    json["effects"]["av_marker"] = {{"times_s", {1.0, 1.3}}, {"flash_ms", 200}};
    require_error(json, "'av_marker'", "closer than two flashes (400 ms)");
    json["effects"]["av_marker"] = {{"times_s", nlohmann::json::array()}, {"flash_ms", 200}};
    require_error(json, "'av_marker'", "times_s");
    json["effects"]["av_marker"] = {{"times_s", std::vector<double>(65, 1.0)}, {"flash_ms", 200}};
    require_error(json, "'av_marker'", "times_s");
    json["effects"]["av_marker"] = {{"times_s", {1.0}}, {"flash_ms", 0}};
    require_error(json, "'av_marker'", "'flash_ms' must be in [10, 2000]");
  }
  SECTION("color gain for a camera the sites do not have") {
    nlohmann::json json = clap_json();
    json["effects"]["color_gain"] = {{"cameras", {{"middle-left", {{"gain", 1.0}, {"white_balance", {1, 1, 1}}}}}}};
    require_error(json, "unknown camera 'middle-left'", "top-left");
  }
  SECTION("unknown motion") {
    nlohmann::json json = clap_json();
    json["sites"]["B"]["motion"]["name"] = "high_five";
    require_error(json, "site B motion", "unknown motion 'high_five'");
  }
  SECTION("touch target off the screen") {
    nlohmann::json json = clap_json();
    json["sites"]["A"]["motion"]["touch_target_m"] = {0.9, 0.0};
    require_error(json, "site A motion", "'touch_target_m' lies outside the screen");
  }
  SECTION("touch target out of reach") {
    nlohmann::json json = clap_json();
    json["sites"]["A"]["motion"]["touch_target_m"] = {-0.65, 0.35};
    require_error(json, "site A motion", "out of reach");
  }
  SECTION("site file that does not exist") {
    nlohmann::json json = clap_json();
    json["sites"]["A"]["site"] = "../sites/nowhere.json";
    require_error(json, "site A: field 'site'", "nowhere.json' does not exist");
  }
  SECTION("site file that is broken") {
    const std::filesystem::path dir = rt::test::output_dir("test_sim_scene");
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "broken-site.json") << R"({"name": "broken"})";
    nlohmann::json json = clap_json();
    json["sites"]["B"]["site"] = (dir / "broken-site.json").string();
    require_error(json, "site B: field 'site'", "broken-site.json': missing field 'screen'");
  }
  SECTION("missing site") {
    nlohmann::json json = clap_json();
    json["sites"].erase("B");
    require_error(json, "sites: missing field 'B'");
  }
  SECTION("a third site") {
    nlohmann::json json = clap_json();
    json["sites"]["C"] = json["sites"]["A"];
    require_error(json, "unknown field 'C'");
  }
  SECTION("user color out of range") {
    nlohmann::json json = clap_json();
    json["sites"]["A"]["user"]["skin_rgb"] = {1.2, 0.5, 0.5};
    require_error(json, "site A user", "'skin_rgb'");
  }
  SECTION("user hand scale missing") {
    nlohmann::json json = clap_json();
    json["sites"]["B"]["user"].erase("hand_scale");
    require_error(json, "site B user", "missing field 'hand_scale'");
  }
  SECTION("misspelt top-level field") {
    nlohmann::json json = clap_json();
    json["effect"] = nlohmann::json::object();
    require_error(json, "unknown field 'effect'");
  }
}

TEST_CASE("a scene file that is missing or not JSON is named", "[sim][scene]") {
  const std::filesystem::path dir = rt::test::output_dir("test_sim_scene");
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH(load_scene(dir / "no-such-scene.json"), Contains("no-such-scene.json"));
  std::ofstream(dir / "half-scene.json") << R"({"name": "half", "frames": )";
  CHECK_THROWS_WITH(load_scene(dir / "half-scene.json"), Contains("half-scene.json") && Contains("not valid JSON"));
  // Site paths resolve against the scene file's folder, wherever the scene is read from.
  nlohmann::json json = clap_json();
  for (const char* site : {"A", "B"})
    json["sites"][site]["site"] = std::filesystem::relative(kScenesSimScene / "../sites/default.json", dir).string();
  config::write_json_file(dir / "moved-clap.json", json);
  CHECK(load_scene(dir / "moved-clap.json").at(Site::B).site.cameras.size() == 6);
  json["frames"] = 0;
  config::write_json_file(dir / "zero-frames.json", json);
  CHECK_THROWS_WITH(load_scene(dir / "zero-frames.json"), Contains("zero-frames.json") && Contains("'frames'"));
}
