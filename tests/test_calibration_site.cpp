// Calibration writes the one site file the rest reads: synthetic data calibrated into a copy of
// the shipped default site gives back the poses through load_site(), keeps what calibration does
// not measure, drives the simulated tracker through a scene; and the refusals (no site file, a
// foreign file, a camera the site does not have, another screen, a result that fails the checks).
#include <catch2/catch.hpp>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "config/assets.h"
#include "calibration/calibration_error.h"
#include "calibration/extrinsics_calibration.h"
#include "calibration/site_update.h"
#include "calibration/synthetic_site.h"
#include "calibration/tracker_calibration.h"
#include "config/json.h"
#include "sim/default_site.h"
#include "sim/motion.h"
#include "sim/scene.h"
#include "sim/tracker_sim.h"

using namespace rt;
using namespace rt::calibration;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kAssets = rt::config::assets_dir();
constexpr double kDegreeCalibrationSite = 3.14159265358979323846 / 180.0;
// The synthetic data's noise (0.1 px corners, 1 mm distances, 2 mm fingertips) bounds how well
// the poses come back; the bounds are those of test_calibration_extrinsics and _tracker.
constexpr double kCameraPositionToleranceM = 10e-3;
constexpr double kCameraAngleToleranceRad = 0.5 * kDegreeCalibrationSite;
constexpr double kTrackerPositionToleranceM = 4e-3;
constexpr double kTrackerAngleToleranceRad = 0.6 * kDegreeCalibrationSite;

std::filesystem::path scratch_file(const std::string& name) {
  const auto folder =
      std::filesystem::temp_directory_path() / ("remotetouch-test-calibration-site-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  return folder / name;
}

// What a user does first: copy the shipped default site.
std::filesystem::path copy_of_default_site(const std::string& name) {
  const auto path = scratch_file(name);
  std::filesystem::copy_file(kAssets / "sites" / "default.json", path, std::filesystem::copy_options::overwrite_existing);
  return path;
}

std::string file_text(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

double angle_between_calibration_site(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle();
}

const SyntheticSite& synthetic() {
  static const SyntheticSite site = make_synthetic_site();
  return site;
}

}  // namespace

TEST_CASE("Synthetic data calibrated into a copy of the default site: load_site gives back the poses",
          "[calibration][site]") {
  const SyntheticSite& truth = synthetic();
  const auto path = copy_of_default_site("round-trip.json");

  // `calibrate extrinsics --site`, then `calibrate tracker --site`, as the commands do it.
  sim::SiteDescription site = load_site_to_update(path);
  const ExtrinsicsResult cameras = calibrate_extrinsics(truth.extrinsics_input);
  CHECK(apply_camera_calibration(site, cameras, truth.extrinsics_input.screen).empty());
  write_updated_site(path, site);
  site = load_site_to_update(path);
  const TrackerCalibration tracker = calibrate_tracker(truth.touches);
  apply_tracker_calibration(site, tracker);
  write_updated_site(path, site);

  const sim::SiteDescription read = sim::load_site(path);
  const sim::SiteDescription shipped = sim::load_site(kAssets / "sites" / "default.json");
  REQUIRE(read.cameras.size() == truth.truth.cameras.size());
  for (size_t i = 0; i < read.cameras.size(); ++i) {
    const sim::RgbdCamera& found = read.cameras[i];
    const sim::RgbdCamera& expected = truth.truth.cameras[i];
    INFO("camera " << expected.name);
    CHECK(found.name == expected.name);
    CHECK((found.color_camera().position_in_site() - expected.color_camera().position_in_site()).norm() <
          kCameraPositionToleranceM);
    CHECK(angle_between_calibration_site(found.camera_from_site, expected.camera_from_site) < kCameraAngleToleranceRad);
    // The color intrinsics are the calibrated ones (here: the inputs'), with their distortion.
    const CameraIntrinsics& calibrated = truth.extrinsics_input.cameras[i].intrinsics;
    CHECK(found.color.fx == Approx(calibrated.fx).epsilon(1e-12));
    CHECK(found.color.cy == Approx(calibrated.cy).epsilon(1e-12));
    CHECK(found.color.distortion.k1 == Approx(calibrated.distortion.k1).epsilon(1e-12));
    // What calibration does not measure stays as the site file had it.
    CHECK(found.depth.fx == shipped.cameras[i].depth.fx);
    CHECK(found.depth.width == shipped.cameras[i].depth.width);
    CHECK(found.depth_max_m == shipped.cameras[i].depth_max_m);
  }
  const Eigen::Isometry3d& expected_tracker = truth.truth.tracker.site_from_tracker;
  CHECK((read.tracker.site_from_tracker.translation() - expected_tracker.translation()).norm() <
        kTrackerPositionToleranceM);
  CHECK(angle_between_calibration_site(read.tracker.site_from_tracker, expected_tracker) < kTrackerAngleToleranceRad);
  REQUIRE(read.tracker.rms_residual_mm);
  CHECK(*read.tracker.rms_residual_mm == Approx(tracker.inlier_rms_mm).epsilon(1e-12));
  CHECK(read.name == shipped.name);
  CHECK(read.seat.head_centre_m == shipped.seat.head_centre_m);
  CHECK(read.touch_region.centre_m == shipped.touch_region.centre_m);
  CHECK(read.touch_region.half_size_m == shipped.touch_region.half_size_m);
  CHECK(read.motor_position_m == shipped.motor_position_m);
  CHECK(read.tracker.range.max_distance_m == shipped.tracker.range.max_distance_m);
  CHECK_FALSE(shipped.tracker.rms_residual_mm);
}

TEST_CASE("A scene naming the calibrated site file drives the simulated tracker with the calibrated pose",
          "[calibration][site][sim]") {
  // The site file the user started from has the tracker where they guessed it: 4 cm off and
  // turned; the calibration puts it where it is.
  sim::SiteDescription guess = sim::make_default_site();
  guess.tracker.site_from_tracker.translation() += Eigen::Vector3d(0.03, -0.02, 0.02);
  guess.tracker.site_from_tracker.linear() =
      Eigen::AngleAxisd(4 * kDegreeCalibrationSite, Eigen::Vector3d::UnitY()) * guess.tracker.site_from_tracker.linear();
  const auto site_path = scratch_file("guessed-tracker.json");
  sim::write_site(site_path, guess);

  sim::SiteDescription site = load_site_to_update(site_path);
  const TrackerCalibration calibrated = calibrate_tracker(synthetic().touches);
  apply_tracker_calibration(site, calibrated);
  write_updated_site(site_path, site);

  nlohmann::json scene_json = config::read_json_file(kAssets / "scenes" / "clap.json");
  scene_json["sites"]["A"]["site"] = site_path.string();
  scene_json["sites"]["B"]["site"] = (kAssets / "sites" / "default.json").string();
  const auto scene_path = scratch_file("calibrated-clap.json");
  config::write_json_file(scene_path, scene_json);
  const sim::Scene scene = sim::load_scene(scene_path);
  const sim::SiteSetup& setup = scene.at(Site::A);
  CHECK((setup.site.tracker.site_from_tracker.matrix() - calibrated.site_from_tracker.matrix()).norm() < 1e-12);
  CHECK((calibrated.site_from_tracker.translation() - guess.tracker.site_from_tracker.translation()).norm() > 0.03);

  const sim::MotionTrack track(setup.motion, setup.site.seat, setup.user);
  sim::SimulatedHandTracker device = sim::make_simulated_tracker(scene, Site::A);
  int hands = 0;
  while (std::optional<sim::TrackerFrame> frame = device.next_frame())
    for (const sim::TrackerHand& hand : frame->hands) {
      const Eigen::Vector3d truth_palm = track.pose_at(frame->timestamp_us * 1e-6).right_hand.palm;
      CHECK((hand.palm_position - 1000.0 * (calibrated.site_from_tracker.inverse() * truth_palm)).norm() < 1e-3);
      ++hands;
    }
  CHECK(hands > 25);
}

TEST_CASE("Calibration refuses a site file it cannot update, and leaves it as it was", "[calibration][site]") {
  const SyntheticSite& truth = synthetic();
  SECTION("no site file yet") {
    CHECK_THROWS_WITH(load_site_to_update(scratch_file("no-such-site.json")),
                      Contains("does not exist") && Contains("copy of assets/sites/default.json"));
  }
  SECTION("a file that is not a site file, such as an old site calibration") {
    const auto path = scratch_file("old-calibration.json");
    const nlohmann::json old = {{"screen", {{"width_m", 1.439}, {"height_m", 0.809}}},
                                {"tracker", {{"site_from_tracker", isometry_to_json(Eigen::Isometry3d::Identity())},
                                             {"tracker_unit", "mm"}}}};
    config::write_json_file(path, old);
    const std::string before = file_text(path);
    CHECK_THROWS_WITH(load_site_to_update(path),
                      Contains("old-calibration.json' is not a site file to update") && Contains("missing field 'name'"));
    CHECK(file_text(path) == before);
  }
  SECTION("a site file with the old tracker convention") {
    const auto path = copy_of_default_site("old-convention.json");
    nlohmann::json json = config::read_json_file(path);
    json["tracker"]["tracker_from_site"] = json["tracker"]["site_from_tracker"];
    json["tracker"].erase("site_from_tracker");
    config::write_json_file(path, json);
    CHECK_THROWS_WITH(load_site_to_update(path), Contains("'tracker_from_site' is the old convention"));
  }
  SECTION("a calibrated camera the site file does not have") {
    sim::SiteDescription site = sim::make_default_site();
    site.cameras[2].name = "upper-right";
    CHECK_THROWS_WITH(check_cameras_fit_site(site, {"top-left", "top-right"}, site.screen),
                      Contains("camera 'top-right' is not in the site file") && Contains("'upper-right'"));
    const ExtrinsicsResult cameras = calibrate_extrinsics(truth.extrinsics_input);
    const sim::SiteDescription before = site;
    CHECK_THROWS_AS(apply_camera_calibration(site, cameras, truth.extrinsics_input.screen), CalibrationError);
    CHECK(site.cameras[0].camera_from_site.matrix() == before.cameras[0].camera_from_site.matrix());
  }
  SECTION("cameras calibrated against another screen") {
    const sim::SiteDescription site = sim::make_default_site();
    Screen smaller = site.screen;
    smaller.width_m = 1.21;  // a 55-inch panel
    CHECK_THROWS_WITH(check_cameras_fit_site(site, {"top-left"}, smaller),
                      Contains("1.210 x 0.809 m screen") && Contains("the site file has 1.439 x 0.809 m"));
  }
  SECTION("a result that fails the site's checks is not written") {
    const auto path = copy_of_default_site("fails-checks.json");
    const std::string before = file_text(path);
    sim::SiteDescription site = load_site_to_update(path);
    TrackerCalibration upside_down;
    upside_down.site_from_tracker = site.tracker.site_from_tracker *
                                    Eigen::Isometry3d(Eigen::AngleAxisd(180 * kDegreeCalibrationSite, Eigen::Vector3d::UnitX()));
    apply_tracker_calibration(site, upside_down);
    CHECK_THROWS_WITH(write_updated_site(path, site),
                      Contains("fails its checks") && Contains("does not see the touch region"));
    CHECK(file_text(path) == before);
  }
  SECTION("a non-finite number is not written") {
    const auto path = copy_of_default_site("nan.json");
    const std::string before = file_text(path);
    sim::SiteDescription site = load_site_to_update(path);
    site.cameras[4].color.cy = std::nan("");
    CHECK_THROWS_WITH(write_updated_site(path, site), Contains("cameras/4/cy is not finite"));
    CHECK(file_text(path) == before);
  }
}

TEST_CASE("The synthetic site's truth is itself a valid site file", "[calibration][site]") {
  const auto folder = scratch_file("synthetic");
  write_synthetic_site(synthetic(), folder);
  const sim::SiteDescription read = sim::load_site(folder / "truth_site.json");
  REQUIRE(read.cameras.size() == 6);
  CHECK((read.tracker.site_from_tracker.matrix() - synthetic().truth.tracker.site_from_tracker.matrix()).norm() < 1e-12);
  CHECK(read.cameras[3].color.distortion.k1 == synthetic().truth.cameras[3].color.distortion.k1);
}
