// `calibrate extrinsics --views-from`: the chessboard views taken from k4a recordings of the
// site's cameras. A synthetic site's board poses are rendered through each camera's real lens,
// written as MJPG recordings, found again in the decoded images, and the cameras calibrated from
// them with their recorded factory intrinsics; the poses must come back as the truth.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "calibration/calibration_error.h"
#include "calibration/extrinsics_calibration.h"
#include "calibration/synthetic_site.h"
#include "camera/recorded_board_views.h"
#include "camera/recorded_site.h"
#include "camera/synthetic_board_recording.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::calibration;
using Catch::Matchers::Contains;

namespace {

constexpr double kRecordedDegree = 3.14159265358979323846 / 180.0;
// Exact distances; the corners found in rendered, MJPG-compressed images (quality 90) of a board
// held 0.4 to 0.64 m away.
constexpr double kRecordedPositionToleranceM = 1.0e-3;
constexpr double kRecordedAngleToleranceRad = 0.05 * kRecordedDegree;

struct RecordedBoardSite {
  SyntheticSite site;
  std::filesystem::path dir;
};

const RecordedBoardSite& recorded_board_site() {
  static const RecordedBoardSite recorded = [] {
    SyntheticSiteOptions options;
    options.distance_noise_mm = 0.0;
    options.board_poses = 12;
    RecordedBoardSite made{make_synthetic_site(options), rt::test::output_dir("test_calibration_recorded_views") / "boards"};
    std::filesystem::remove_all(made.dir);
    camera::write_board_recording(made.site, made.dir, 90);
    return made;
  }();
  return recorded;
}

// The input a user writes: the board, the screen, each camera's distances; no views, no lenses.
ExtrinsicsInput input_without_views(const SyntheticSite& site) {
  ExtrinsicsInput input = site.extrinsics_input;
  input.snapshots.clear();
  for (CameraSetup& camera : input.cameras) {
    camera.intrinsics = {};
    camera.intrinsics_given = false;
  }
  return input;
}

}  // namespace

TEST_CASE("Chessboard views from the cameras' recordings calibrate the site", "[calibration][k4a]") {
  const RecordedBoardSite& recorded = recorded_board_site();
  ExtrinsicsInput input = input_without_views(recorded.site);
  const auto recording = camera::open_recorded_site(recorded.dir);
  const camera::RecordedBoardViews found = camera::add_recorded_board_views(input, *recording, 0.5, "test");
  INFO("views found " << found.views_added << " of " << found.frame_sets_searched);
  CHECK(found.frame_sets_searched == recorded.site.site_from_board.size());
  // Every pose was seen whole by at least two cameras when the site was made.
  CHECK(found.views_added == recorded.site.site_from_board.size());

  // The lenses are the devices' factory calibration, as the recording stores it.
  for (size_t c = 0; c < input.cameras.size(); ++c) {
    const CameraIntrinsics& truth = recorded.site.truth.cameras[c].color;
    const CameraIntrinsics& taken = input.cameras[c].intrinsics;
    INFO("camera " << input.cameras[c].name);
    CHECK(input.cameras[c].intrinsics_given);
    CHECK(taken.width == truth.width);
    CHECK(taken.fx == Approx(truth.fx).epsilon(1e-5));
    CHECK(taken.cy == Approx(truth.cy).epsilon(1e-5));
    CHECK(taken.distortion.p1 == Approx(truth.distortion.p1).margin(1e-7));
    CHECK(taken.distortion.p2 == Approx(truth.distortion.p2).margin(1e-7));
  }

  size_t observations = 0, expected_observations = 0;
  for (const BoardSnapshot& snapshot : input.snapshots) observations += snapshot.observations.size();
  for (const BoardSnapshot& snapshot : recorded.site.extrinsics_input.snapshots)
    expected_observations += snapshot.observations.size();
  // A camera that sees the board whole finds it; the synthetic site counted those.
  CHECK(observations >= expected_observations * 9 / 10);

  const ExtrinsicsResult result = calibrate_extrinsics(input);
  REQUIRE(result.cameras.size() == recorded.site.truth.cameras.size());
  for (size_t i = 0; i < result.cameras.size(); ++i) {
    const Camera& calibrated = result.cameras[i].camera;
    const Camera truth = recorded.site.truth.cameras[i].color_camera();
    INFO("camera " << truth.name << ", link RMS " << result.cameras[i].link.rms_error_px << " px");
    REQUIRE(calibrated.camera_from_site.matrix().allFinite());
    const double position_error_m = (calibrated.position_in_site() - truth.position_in_site()).norm();
    const double angle_error_rad =
        Eigen::AngleAxisd(calibrated.camera_from_site.linear() * truth.camera_from_site.linear().transpose()).angle();
    INFO("position off by " << position_error_m * 1e3 << " mm, turned by " << angle_error_rad / kRecordedDegree << " deg");
    CHECK(position_error_m < kRecordedPositionToleranceM);
    CHECK(angle_error_rad < kRecordedAngleToleranceRad);
    CHECK(result.cameras[i].link.rms_error_px < 0.5);
  }
}

TEST_CASE("Views from a recording: one frame set per interval, and what does not fit is refused", "[calibration][k4a]") {
  const RecordedBoardSite& recorded = recorded_board_site();
  const auto recording = camera::open_recorded_site(recorded.dir);

  SECTION("an interval longer than the recording searches its first set only") {
    ExtrinsicsInput input = input_without_views(recorded.site);
    const auto found = camera::add_recorded_board_views(input, *recording, 1e6, "test");
    CHECK(found.frame_sets_searched == 1);
    CHECK(input.snapshots.size() <= 1);
  }
  SECTION("every 2.5 s of poses held a second each: every third set") {
    ExtrinsicsInput input = input_without_views(recorded.site);
    const auto found = camera::add_recorded_board_views(input, *recording, 2.5, "test");
    CHECK(found.frame_sets_searched == (recorded.site.site_from_board.size() + 2) / 3);
  }
  SECTION("a camera the recording does not have") {
    ExtrinsicsInput input = input_without_views(recorded.site);
    input.cameras[1].name = "bottom-middle";
    CHECK_THROWS_AS(camera::add_recorded_board_views(input, *recording, 0.5, "test"), CalibrationError);
    CHECK_THROWS_WITH(camera::add_recorded_board_views(input, *recording, 0.5, "test"),
                      Contains("'bottom-middle'") && Contains("'top-left'"));
  }
  SECTION("intrinsics given for another image size") {
    ExtrinsicsInput input = input_without_views(recorded.site);
    input.cameras[0].intrinsics_given = true;
    input.cameras[0].intrinsics = scaled_intrinsics(recorded.site.truth.cameras[0].color, 0.5);
    CHECK_THROWS_WITH(camera::add_recorded_board_views(input, *recording, 0.5, "test"),
                      Contains("640x360") && Contains("1280x720"));
  }
  SECTION("a negative or NaN interval") {
    ExtrinsicsInput input = input_without_views(recorded.site);
    CHECK_THROWS_AS(camera::add_recorded_board_views(input, *recording, -1.0, "test"), CalibrationError);
    CHECK_THROWS_AS(camera::add_recorded_board_views(input, *recording, std::nan(""), "test"), CalibrationError);
  }
}

TEST_CASE("An input for a recording may leave out its views and lenses; one for images may not", "[calibration]") {
  const nlohmann::json json = {
      {"board", {{"inner_corners", "9x6"}, {"square_m", 0.05}}},
      {"cameras",
       {{{"name", "top-left"},
         {"screen_corner_distances_m", {{"top_left", 0.2}, {"top_right", 1.5}, {"bottom_right", 1.7}, {"bottom_left", 0.8}}}}}}};
  const ExtrinsicsInput input = extrinsics_input_from_json(json, ".", "input", ViewsFrom::Recording);
  CHECK_FALSE(input.cameras[0].intrinsics_given);
  CHECK(input.snapshots.empty());
  CHECK_THROWS_WITH(extrinsics_input_from_json(json, ".", "input"), Contains("intrinsics"));
  nlohmann::json with_image = json;
  with_image["views"] = {{{"cameras", {{"top-left", {{"image", "v.png"}}}}}}};
  CHECK_THROWS_WITH(extrinsics_input_from_json(with_image, ".", "input", ViewsFrom::Recording),
                    Contains("needs the camera's 'intrinsics'"));
}
