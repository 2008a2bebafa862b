// The site descriptions of the simulator: the shipped files are what the generator makes, every
// camera sees the seated user, the tracker covers the touch region, and a bad file is refused
// with an error that names the field or the camera.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "config/assets.h"
#include "config/json.h"
#include "sim/default_site.h"
#include "sim/site_description.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::sim;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kSites = rt::config::assets_dir() / "sites";

double radians(double degrees) { return degrees * std::numbers::pi / 180; }
double degrees(double radians) { return radians * 180 / std::numbers::pi; }

// Where two JSON documents differ ("" if nowhere); numbers within `tolerance` count as equal, so a
// different compiler's last-bit rounding does not fail the comparison.
std::string first_difference(const nlohmann::json& a, const nlohmann::json& b, const std::string& path = "",
                             double tolerance = 1e-12) {
  if (a.is_number() && b.is_number())
    return std::abs(a.get<double>() - b.get<double>()) <= tolerance ? "" : path + ": " + a.dump() + " vs " + b.dump();
  if (a.type() != b.type() || a.size() != b.size()) return path + ": " + a.dump() + " vs " + b.dump();
  if (a.is_object()) {
    for (const auto& [key, value] : a.items()) {
      if (!b.contains(key)) return path + "/" + key + ": missing";
      if (std::string d = first_difference(value, b[key], path + "/" + key, tolerance); !d.empty()) return d;
    }
    return "";
  }
  if (a.is_array()) {
    for (size_t i = 0; i < a.size(); ++i)
      if (std::string d = first_difference(a[i], b[i], path + "/" + std::to_string(i), tolerance); !d.empty()) return d;
    return "";
  }
  return a == b ? "" : path + ": " + a.dump() + " vs " + b.dump();
}

nlohmann::json default_json() { return site_to_json(make_default_site()); }

void require_error_sim_site(const nlohmann::json& json, const std::string& part1, const std::string& part2 = "") {
  try {
    site_from_json(json, "site 'test'");
    FAIL("accepted a bad site description");
  } catch (const config::JsonError& error) {
    CHECK_THAT(error.what(), Contains(part1) && Contains(part2) && Contains("site 'test'"));
  }
}

}  // namespace

TEST_CASE("shipped site files match the generator", "[sim][site]") {
  for (const ShippedSite& shipped : shipped_sites()) {
    INFO(shipped.file_name << ": regenerate with `test_sim_site \"[.regenerate]\"`");
    const nlohmann::json on_disk = config::read_json_file(kSites / shipped.file_name);
    CHECK(first_difference(on_disk, site_to_json(make_default_site(shipped.options))) == "");
    // And reading it gives back what it says.
    const SiteDescription loaded = load_site(kSites / shipped.file_name);
    CHECK(site_to_json(loaded) == on_disk);
  }
}

TEST_CASE("regenerate the shipped site files", "[.regenerate]") {
  for (const ShippedSite& shipped : shipped_sites())
    config::write_json_file(kSites / shipped.file_name, site_to_json(make_default_site(shipped.options)));
}

TEST_CASE("the default site: screen, six cameras around it, tracker, motor, seat", "[sim][site]") {
  const SiteDescription site = load_site(kSites / "default.json");
  CHECK(site.screen.width_m == Approx(1.439));
  CHECK(site.screen.height_m == Approx(0.809));
  CHECK((site.seat.head_centre_m - Eigen::Vector3d(0, 0.1, 0.7)).norm() < 1e-12);
  REQUIRE(site.cameras.size() == 6);
  for (const char* name : {"top-left", "top-centre", "top-right", "bottom-left", "bottom-centre", "bottom-right"}) {
    INFO(name);
    const RgbdCamera* camera = site.find_camera(name);
    REQUIRE(camera != nullptr);
    const Eigen::Vector3d position = camera->color_camera().position_in_site();
    // Just outside the screen rectangle, a few centimetres in front of the glass.
    CHECK_FALSE(site.screen.contains(position.head<2>()));
    CHECK(std::abs(position.y()) < site.screen.height_m / 2 + 0.1);
    CHECK(std::abs(position.x()) < site.screen.width_m / 2 + 0.1);
    CHECK(position.z() == Approx(0.03));
    const std::string name_text = name;
    if (name_text.find("left") != std::string::npos) CHECK(position.x() < -site.screen.width_m / 2);
    if (name_text.find("right") != std::string::npos) CHECK(position.x() > site.screen.width_m / 2);
    if (name_text.find("centre") != std::string::npos) CHECK(position.x() == Approx(0.0).margin(1e-12));
    if (name_text.find("top") == 0) CHECK(position.y() > site.screen.height_m / 2);
    if (name_text.find("bottom") == 0) CHECK(position.y() < -site.screen.height_m / 2);
    // Color 16:9 at about 90 x 59 degrees; depth 512x512 at 120 degrees, 0.25-2.88 m.
    CHECK(camera->color.width == 1280);
    CHECK(camera->color.height == 720);
    const double color_h = degrees(2 * std::atan(camera->color.width / 2.0 / camera->color.fx));
    const double color_v = degrees(2 * std::atan(camera->color.height / 2.0 / camera->color.fy));
    CHECK(color_h == Approx(90.0).margin(1.0));
    CHECK(color_v == Approx(59.0).margin(1.0));
    CHECK(camera->depth.width == 512);
    CHECK(camera->depth.height == 512);
    CHECK(degrees(2 * std::atan(256.0 / camera->depth.fx)) == Approx(120.0).margin(0.5));
    CHECK(camera->depth_min_m == 0.25);
    CHECK(camera->depth_max_m == 2.88);
    CHECK(camera->color.distortion.as_opencv() == Distortion{}.as_opencv());
    // Color and depth share the pose; the optical axis points at the user, image up is site up.
    const Eigen::Vector3d forward = camera->camera_from_site.linear().row(2).transpose();
    CHECK(forward.z() > 0.5);
    const Eigen::Vector3d down = camera->camera_from_site.linear().row(1).transpose();
    CHECK(down.y() < -0.5);
  }
  const Eigen::Vector3d tracker = site.tracker.site_from_tracker.translation();
  CHECK(tracker.z() == Approx(0.5));  // 0.5 m from the screen
  CHECK(tracker.x() > 0.0);           // on the right-hand side
  CHECK(tracker.y() < site.touch_region.centre_m.y());  // below the hand
  const Eigen::Vector3d tracker_up = site.tracker.site_from_tracker.linear().col(1);
  CHECK(tracker_up.y() > 0.3);   // faces up...
  CHECK(tracker_up.z() < -0.3);  // ...and towards the screen, where the touch region is
  CHECK((site.motor_position_m - Eigen::Vector3d(-1.439 / 2, 0.809 / 2, 0)).norm() < 1e-12);

  const SiteDescription paper = load_site(kSites / "paper.json");
  CHECK(paper.cameras.at(0).color.width == 2560);
  CHECK(paper.cameras.at(0).color.height == 1440);
}

TEST_CASE("the top row sees the seated user's head and chest, the bottom row chest and waist", "[sim][site]") {
  const SiteDescription site = load_site(kSites / "default.json");
  const Eigen::Vector3d head = site.seat.head_centre_m, chest = site.seat.chest_m();
  for (const RgbdCamera& camera : site.cameras) {
    INFO(camera.name);
    const bool top_row = camera.color_camera().position_in_site().y() > 0;
    CHECK(camera.why_unseen(chest) == "");
    // Each row's aim is near the middle of its image: the head for the top row, the waist for the bottom.
    const Eigen::Vector3d aim = top_row ? head : head - Eigen::Vector3d(0, 0.5, 0);
    CHECK(camera.why_unseen(aim) == "");
    const Eigen::Vector2d pixel = *camera.color_camera().project(aim);
    CHECK(std::abs(pixel.x() - camera.color.cx) < 0.25 * camera.color.width);
    CHECK(std::abs(pixel.y() - camera.color.cy) < 0.25 * camera.color.height);
    // And nothing behind the glass.
    CHECK_FALSE(camera.sees({0.0, 0.0, -0.2}));
  }
}

TEST_CASE("what the remote eye sees of the seated user through the screen, the cameras see", "[sim][site]") {
  // The portrait shows the user from the other site's seat, mapped here (DESIGN.md section 2):
  // every point of the user's front that this eye sees through the screen must be seen by two
  // color cameras, and by one of each four the image-based model selects (the two central ones
  // and one side's two). With all six cameras aimed at the face, the bottom of the torso was seen
  // by none.
  const SiteDescription site = load_site(kSites / "default.json");
  const Eigen::Vector3d eye(site.seat.head_centre_m.x(), site.seat.head_centre_m.y(), -site.seat.head_centre_m.z());
  const std::vector<std::vector<std::string>> selections = {
      {"top-centre", "bottom-centre", "top-left", "bottom-left"}, {"top-centre", "bottom-centre", "top-right", "bottom-right"}};
  int checked = 0;
  for (double y = -0.65; y <= 0.25; y += 0.05)
    for (double x = -0.25; x <= 0.25; x += 0.05) {
      const Eigen::Vector3d point(x, y, 0.55);  // the front of a seated user's torso and face
      const Eigen::Vector3d on_glass = eye + (point - eye) * (-eye.z() / (point.z() - eye.z()));
      if (!site.screen.contains(on_glass.head<2>())) continue;
      ++checked;
      INFO("point " << point.transpose());
      int seen_by = 0;
      for (const RgbdCamera& camera : site.cameras) seen_by += camera.sees(point);
      CHECK(seen_by >= 2);
      for (const auto& selection : selections) {
        int seen_by_selection = 0;
        for (const std::string& name : selection) seen_by_selection += site.find_camera(name)->sees(point);
        CHECK(seen_by_selection >= 1);
      }
    }
  CHECK(checked > 150);
}

TEST_CASE("the tracker sees the touch region, from the glass up to a raised hand", "[sim][site]") {
  const SiteDescription site = load_site(kSites / "default.json");
  for (double height : {kTouchRegionLowM, 0.05, kTouchRegionHighM})
    for (const Eigen::Vector3d& point : site.touch_region.sample_points(height)) {
      INFO(point.transpose());
      CHECK(site.tracker.sees(point));
    }
  // But not the user's lap, nor the far side of the screen.
  CHECK_FALSE(site.tracker.sees({0.16, -0.51, 0.53}));
  CHECK_FALSE(site.tracker.sees({-0.7, 0.35, 0.02}));
}

TEST_CASE("tracking range: distance and field of view", "[sim][site]") {
  const TrackingRange range;
  CHECK(range.contains({0.0, 0.3, 0.0}));
  CHECK_FALSE(range.contains({0.0, 0.05, 0.0}));   // too near
  CHECK_FALSE(range.contains({0.0, 0.85, 0.0}));   // too far
  CHECK_FALSE(range.contains({0.0, -0.3, 0.0}));   // below the device
  // Each point is within the distance range; only its angle decides.
  CHECK(range.contains({0.2 * std::tan(radians(65)), 0.2, 0.0}));
  CHECK_FALSE(range.contains({0.2 * std::tan(radians(75)), 0.2, 0.0}));  // beyond 70 degrees in x
  CHECK(range.contains({0.0, 0.3, 0.3 * std::tan(radians(55))}));
  CHECK_FALSE(range.contains({0.0, 0.3, 0.3 * std::tan(radians(65))}));  // beyond 60 degrees in z
}

TEST_CASE("bad site descriptions name the field or the camera", "[sim][site]") {
  SECTION("missing intrinsic") {
    nlohmann::json json = default_json();
    json["cameras"][0].erase("fx");
    require_error_sim_site(json, "'fx'", "top-left");
  }
  SECTION("wrong type") {
    nlohmann::json json = default_json();
    json["cameras"][2]["depth"]["width"] = "512";
    require_error_sim_site(json, "'width'", "top-right");
  }
  SECTION("missing pose") {
    nlohmann::json json = default_json();
    json["cameras"][1].erase("camera_from_site");
    require_error_sim_site(json, "'camera_from_site'", "top-centre");
  }
  SECTION("pose that is not a rotation") {
    nlohmann::json json = default_json();
    json["cameras"][1]["camera_from_site"][0][0] = 2.0;
    require_error_sim_site(json, "not a rotation", "top-centre");
  }
  SECTION("missing depth range") {
    nlohmann::json json = default_json();
    json["cameras"][3]["depth"].erase("max_range_m");
    require_error_sim_site(json, "'max_range_m'", "bottom-left");
  }
  SECTION("inverted depth range") {
    nlohmann::json json = default_json();
    json["cameras"][3]["depth"]["min_range_m"] = 3.0;
    require_error_sim_site(json, "'max_range_m' must be greater", "bottom-left");
  }
  SECTION("a camera turned away from the user sees nothing of them") {
    SiteDescription site = make_default_site();
    site.cameras[4].camera_from_site =
        camera_from_site_looking_at(site.cameras[4].camera_from_site.inverse().translation(), {0.0, -2.0, -1.0});
    require_error_sim_site(site_to_json(site), "camera 'bottom-centre' cannot see the seated user's chest", "(0, -0.2, 0.7)");
  }
  SECTION("a camera too far for its depth range") {
    SiteDescription site = make_default_site();
    site.cameras[0].depth_max_m = 0.5;
    require_error_sim_site(site_to_json(site), "camera 'top-left'", "beyond the depth range");
  }
  SECTION("a seat the cameras do not see") {
    nlohmann::json json = default_json();
    json["seat"]["head_centre_m"] = {0.0, 2.5, 0.7};
    require_error_sim_site(json, "cannot see the seated user's chest");
  }
  SECTION("a tracker facing away from the touch region") {
    SiteDescription site = make_default_site();
    site.tracker.site_from_tracker =
        site.tracker.site_from_tracker * Eigen::Isometry3d(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()));
    require_error_sim_site(site_to_json(site), "tracker", "touch region");
  }
  SECTION("a file with the old tracker convention") {
    nlohmann::json json = default_json();
    json["tracker"]["tracker_from_site"] = json["tracker"]["site_from_tracker"];
    json["tracker"].erase("site_from_tracker");
    require_error_sim_site(json, "field 'tracker_from_site' is the old convention", "'site_from_tracker'");
  }
  SECTION("a negative calibration residual") {
    nlohmann::json json = default_json();
    json["tracker"]["rms_residual_mm"] = -1.0;
    require_error_sim_site(json, "'rms_residual_mm'", "tracker");
  }
  SECTION("unknown and misspelt fields") {
    nlohmann::json json = default_json();
    json["tracker"]["rnage"] = json["tracker"]["range"];
    require_error_sim_site(json, "unknown field 'rnage'", "tracker");
  }
  SECTION("two cameras with one name") {
    nlohmann::json json = default_json();
    json["cameras"][1]["name"] = "top-left";
    require_error_sim_site(json, "two cameras are named 'top-left'");
  }
  SECTION("no cameras") {
    nlohmann::json json = default_json();
    json["cameras"] = nlohmann::json::array();
    require_error_sim_site(json, "'cameras'");
  }
  SECTION("screen width is text") {
    nlohmann::json json = default_json();
    json["screen"]["width_m"] = "wide";
    require_error_sim_site(json, "'width_m' must be a number");
  }
}

TEST_CASE("a site file that is missing or not JSON is named", "[sim][site]") {
  const std::filesystem::path dir = rt::test::output_dir("test_sim_site");
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH(load_site(dir / "no-such-site.json"), Contains("no-such-site.json"));
  const std::filesystem::path broken = dir / "broken-site.json";
  std::ofstream(broken) << "{\"name\": \"x\", ";
  CHECK_THROWS_WITH(load_site(broken), Contains("broken-site.json") && Contains("not valid JSON"));
  const std::filesystem::path incomplete = dir / "incomplete-site.json";
  std::ofstream(incomplete) << "{\"name\": \"x\"}";
  CHECK_THROWS_WITH(load_site(incomplete), Contains("incomplete-site.json") && Contains("missing field 'screen'"));
  const std::filesystem::path huge = dir / "huge-number-site.json";
  std::ofstream(huge) << "{\"name\": 1E999}";
  CHECK_THROWS_AS(load_site(huge), config::JsonError);
  CHECK_THROWS_WITH(load_site(huge), Contains("huge-number-site.json"));
}
