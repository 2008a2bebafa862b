// The site calibration file the rest of the system reads: round trip, partial files, and
// errors that name the field.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "calibration/site_calibration.h"
#include "calibration/synthetic_site.h"
#include "config/json_fields.h"

using namespace rt;
using Catch::Matchers::Contains;

namespace {

std::filesystem::path scratch_file(const std::string& name) {
  const auto folder =
      std::filesystem::temp_directory_path() / ("remotetouch-test-calibration-site-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  return folder / name;
}

SiteCalibration example() { return calibration::make_synthetic_site().truth; }

}  // namespace

TEST_CASE("A site calibration survives the round trip through its file", "[calibration][site]") {
  const SiteCalibration written = example();
  const auto path = scratch_file("site.json");
  write_site_calibration(path, written);
  const SiteCalibration read = read_site_calibration(path);
  CHECK(read.screen.width_m == written.screen.width_m);
  CHECK(read.screen.height_m == written.screen.height_m);
  REQUIRE(read.cameras.size() == 6);
  for (size_t i = 0; i < 6; ++i) {
    CHECK(read.cameras[i].name == written.cameras[i].name);
    CHECK(read.cameras[i].intrinsics.fx == written.cameras[i].intrinsics.fx);
    CHECK(read.cameras[i].intrinsics.distortion.k3 == written.cameras[i].intrinsics.distortion.k3);
    CHECK((read.cameras[i].camera_from_site.matrix() - written.cameras[i].camera_from_site.matrix()).norm() < 1e-15);
  }
  REQUIRE(read.tracker);
  CHECK((read.tracker->site_from_tracker.matrix() - written.tracker->site_from_tracker.matrix()).norm() < 1e-15);
  REQUIRE(read.find_camera("bottom-centre"));
  CHECK(read.find_camera("bottom-centre")->intrinsics.width == 1280);
  CHECK(read.find_camera("nobody") == nullptr);
  // A camera's projection works straight from the file: the screen centre is in view of all.
  for (const Camera& camera : read.cameras) CHECK(camera.project(Eigen::Vector3d(0, 0, 0.7)).has_value());
}

TEST_CASE("A partly calibrated site has no cameras or no tracker yet", "[calibration][site]") {
  SiteCalibration cameras_only = example();
  cameras_only.tracker.reset();
  const auto path = scratch_file("cameras_only.json");
  write_site_calibration(path, cameras_only);
  CHECK_FALSE(read_site_calibration(path).tracker);

  const nlohmann::json tracker_only = {
      {"screen", {{"width_m", 1.439}, {"height_m", 0.809}}},
      {"tracker",
       {{"site_from_tracker", isometry_to_json(Eigen::Isometry3d::Identity())}, {"tracker_unit", "mm"}}}};
  const SiteCalibration read = site_calibration_from_json(tracker_only, "site");
  CHECK(read.cameras.empty());
  REQUIRE(read.tracker);
  CHECK((read.tracker->to_site({1000, 0, 0}) - Eigen::Vector3d(1, 0, 0)).norm() < 1e-12);
}

TEST_CASE("Site calibration errors name the field", "[calibration][site]") {
  const nlohmann::json good = site_calibration_to_json(example());
  auto fails_with = [](const nlohmann::json& broken, const std::string& message) {
    CHECK_THROWS_WITH(site_calibration_from_json(broken, "site 'x'"), Contains(message));
  };
  {
    nlohmann::json broken = good;
    broken.erase("screen");
    fails_with(broken, "site 'x': missing field 'screen'");
  }
  {
    nlohmann::json broken = good;
    broken["screen"]["width_m"] = -1.0;
    fails_with(broken, "site 'x' screen: field 'width_m' must be > 0");
  }
  {
    nlohmann::json broken = good;
    broken["cameras"][2].erase("camera_from_site");
    fails_with(broken, "camera 'top-right': missing field 'camera_from_site'");
  }
  {
    nlohmann::json broken = good;
    broken["cameras"][1]["fx"] = "six hundred";
    fails_with(broken, "site 'x': camera 'top-centre': field 'fx' must be a number");
  }
  {
    nlohmann::json broken = good;
    broken["cameras"][3]["name"] = "top-left";
    fails_with(broken, "camera name 'top-left' appears twice");
  }
  {
    nlohmann::json broken = good;
    broken["tracker"]["tracker_unit"] = "cm";
    fails_with(broken, "field 'tracker_unit' is 'cm'");
  }
  {
    nlohmann::json broken = good;
    broken["tracker"]["site_from_tracker"][0][0] = -1.0;  // a reflection
    fails_with(broken, "site 'x' tracker site_from_tracker: the 3x3 part is not a rotation");
  }
  const auto path = scratch_file("broken.json");
  std::ofstream(path) << "{ not json";
  CHECK_THROWS_WITH(read_site_calibration(path), Contains("is not valid JSON"));
}

TEST_CASE("A site calibration with a non-finite number is not written", "[calibration][site]") {
  SiteCalibration site = example();
  site.cameras[4].intrinsics.cy = std::nan("");
  CHECK_THROWS_WITH(write_site_calibration(scratch_file("nan.json"), site),
                    Contains("camera 'bottom-centre'") && Contains("not finite"));
  site = example();
  site.tracker->site_from_tracker.translation().x() = INFINITY;
  CHECK_THROWS_WITH(write_site_calibration(scratch_file("nan.json"), site), Contains("tracker"));
}
