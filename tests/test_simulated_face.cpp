// The simulated user's face (sim/face.h) and the viewpoint a site computes from it: the face
// photograph on the head of a simulated clap frame is found by the Haar cascades in the site's
// cameras at the scene's own resolution, and the eye located from them (triangulated, or placed
// by the depth of the one view that sees the face frontally: viewer/eye_depth.h) lands within 2
// cm of the simulator's true eye; a scene that asks for the seat gets the seat without a search.
//   build/tests/remotetouch_gpu_tests -# "[#test_simulated_face]"
#include <catch2/catch.hpp>

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>
#include <thread>

#include "config/json.h"

#include "pipeline/site_simulator.h"
#include "sim/face.h"
#include "sim/person.h"
#include "sim/scene.h"
#include "site/site_eye.h"
#include "support/gpu_test.h"
#include "viewer/eye_depth.h"
#include "viewer/eye_locator.h"

using namespace rt;

namespace {

// The located eye midpoint against the true one. The viewer's own renders of a flat print at
// 1280x720 stay within 8 mm (test_viewer_renders); here the cameras are 640x360 (an eye ~10 px
// wide, a pixel ~2 mm at the face), the face is curved, and the default stand gives the frontal
// cascade one view only (its corner cameras see the face ~50 degrees aside, its bottom row is
// aimed at the waist), so the depth image places the eyes. 2 cm is what the image of the
// remote user tolerates: a 2 cm eye error moves it by about a centimetre on the screen.
constexpr double kEyeToleranceMm = 20.0;

cv::Mat bgr8(const HostImage& color) {
  cv::Mat bgr(int(color.height), int(color.width), CV_8UC3);
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x)
      for (int c = 0; c < 3; ++c)
        bgr.at<cv::Vec3b>(int(y), int(x))[2 - c] = uint8_t(std::lround(std::clamp(color.at(x, y, uint32_t(c)), 0.0f, 1.0f) * 255));
  return bgr;
}

}  // namespace

TEST_CASE("the face's pupils lie on the front of the head, the eye line level and 63 mm wide", "[face]") {
  const Eigen::Vector3d head(0.0, 0.1, 0.7);
  const sim::TrueEyes eyes = sim::true_eyes_seated(head);
  CHECK((eyes.right - eyes.left).norm() == Approx(0.063).margin(0.001));
  CHECK(eyes.right.x() > eyes.left.x());  // the user's right is +x
  CHECK(eyes.midpoint().z() < head.z() - 0.08);  // on the face, towards the screen
  CHECK(std::abs(eyes.midpoint().x()) < 0.002);
  CHECK(std::abs(eyes.midpoint().y() - head.y() - 0.015) < 0.003);
  // The head leaning towards the screen takes the eyes with it.
  sim::PersonPose pose;
  pose.head_centre = head;
  pose.head_rotation = Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  CHECK(sim::true_eyes(pose).midpoint().y() < eyes.midpoint().y() - 0.02);
  // The pupils sit where the mesh's texture coordinates put the photo's pupils.
  const Eigen::Vector2d right_uv = sim::face_uv(eyes.right - head), left_uv = sim::face_uv(eyes.left - head);
  CHECK(right_uv.x() < left_uv.x());  // the user's right eye is on the photo's left
  for (const Eigen::Vector2d& uv : {right_uv, left_uv}) {
    CHECK(uv.x() > 0.1);
    CHECK(uv.x() < 0.9);
  }
}

TEST_CASE("the face texture: the photo's skin is 1, its edge and border fade to the head's skin", "[face]") {
  std::string why;
  const std::optional<HostImage> texture = sim::load_face_texture(why);
  INFO(why);
  REQUIRE(texture);
  const HostImage& t = *texture;
  for (uint32_t x = 0; x < t.width; ++x) CHECK(t.at(x, 0, 3) == 0.0f);
  for (uint32_t y = 0; y < t.height; ++y) CHECK(t.at(t.width - 1, y, 3) == 0.0f);
  CHECK(t.at(t.width / 2, t.height / 2, 3) == 1.0f);
}

TEST_CASE("a simulated clap frame: the cameras find the face's eyes, located within 2 cm of the true eye", "[face][gpu]") {
  test::NoValidationErrors no_errors;
  // Clap at its own resolution scale (0.5: 640x360 color), as demo runs it; both users (light
  // and dark skin).
  const sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  for (Site site : {Site::A, Site::B}) {
    INFO("site " << site_name(site));
    pipeline::SiteSimulator simulator(test::gpu(), scene, site);
    const std::optional<sim::RgbdFrame> frame = simulator.next_frame();
    REQUIRE(frame);
    std::vector<Camera> cameras, depth_cameras;
    std::vector<cv::Mat> images;
    std::vector<HostImage> depth_images;
    for (size_t k = 0; k < simulator.renderer().camera_count(); ++k) {
      cameras.push_back(simulator.renderer().camera(k).color);
      depth_cameras.push_back(simulator.renderer().camera(k).depth);
      images.push_back(bgr8(frame->cameras[k].color));
      depth_images.push_back(frame->cameras[k].depth_mm);
    }
    EyeDetector detector;
    size_t views_with_face = 0;
    for (const cv::Mat& image : images) views_with_face += detector.detect(image).found();
    const EyePair pair = locate_viewer_eyes_rgbd(detector, cameras, images, depth_cameras, depth_images);
    INFO(pair.message);
    REQUIRE(pair.ok());
    const sim::TrueEyes truth = sim::true_eyes(simulator.last_pose());
    const double error_mm = (pair.midpoint - truth.midpoint()).norm() * 1000.0;
    std::cout << "site " << site_name(site) << ": eyes found in " << views_with_face << " of " << images.size()
              << " views, " << pair.cameras_seeing_eyes.size() << " used; midpoint error " << error_mm << " mm (right eye "
              << (pair.viewer_right - truth.right).norm() * 1000.0 << " mm, left " << (pair.viewer_left - truth.left).norm() * 1000.0
              << " mm)\n";
    CHECK(views_with_face >= 1);
    CHECK(error_mm < kEyeToleranceMm);
    // Without depth the one frontal view cannot place the eyes: the seat would stand.
    if (pair.cameras_seeing_eyes.size() < 2) CHECK_FALSE(locate_viewer_eyes(detector, cameras, images).ok());
  }
}

TEST_CASE("the ground truth is seen from the remote user's true eye, or from the seat where the scene asks", "[face]") {
  sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  const Eigen::Vector3d seat = scene.at(Site::B).site.seat.head_centre_m;
  CHECK((sim::truth_viewer_eye(scene, Site::B) - sim::true_eyes_seated(seat).midpoint()).norm() < 1e-12);
  scene.viewpoint = sim::ViewpointSource::Seat;
  CHECK(sim::truth_viewer_eye(scene, Site::B) == seat);
}

TEST_CASE("a scene's viewpoint option: cameras by default, seat on request, anything else refused", "[face]") {
  const std::filesystem::path file = sim::resolve_scene("clap");
  nlohmann::json json = config::read_json_file(file);
  const std::filesystem::path sites = file.parent_path();
  CHECK(sim::scene_from_json(json, sites, "test").viewpoint == sim::ViewpointSource::Cameras);
  json["viewpoint"] = "seat";
  CHECK(sim::scene_from_json(json, sites, "test").viewpoint == sim::ViewpointSource::Seat);
  json["viewpoint"] = "eyes";
  CHECK_THROWS_WITH(sim::scene_from_json(json, sites, "test"), Catch::Contains("viewpoint must be \"cameras\" or \"seat\""));
}

TEST_CASE("a scene that asks for the seat: no search, the seat's eye from the start, saying why", "[face]") {
  site::EyeSearchOptions options;
  options.use_seat_because = "the scene asks for the seat";
  site::EyeSearch search(options);
  CHECK(search.state() == site::EyeSearch::State::GaveUp);
  CHECK(search.source() == "seat (the scene asks for the seat)");
  const Eigen::Vector3d seat(0, 0.1, 0.7);
  CHECK(search.eye_or(seat) == seat);

  std::vector<std::string> decided;
  std::mutex decided_mutex;
  site::ViewerEyeFinder finder({}, seat, options, [&](const std::string& source) {
    std::lock_guard lock(decided_mutex);
    decided.push_back(source);
  });
  CHECK(finder.decided());
  CHECK_FALSE(finder.wants_frame());
  CHECK(finder.eye() == seat);
  const nlohmann::json json = finder.to_json();
  CHECK(json["source"] == "seat");
  CHECK(json["frames_examined"] == 0);
  CHECK(json["fraction_with_eyes"].is_null());
  for (int i = 0; i < 200; ++i) {
    {
      std::lock_guard lock(decided_mutex);
      if (!decided.empty()) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::lock_guard lock(decided_mutex);
  CHECK(decided == std::vector<std::string>{"seat (the scene asks for the seat)"});
}

TEST_CASE("the eye error's figures: median, 95th percentile, maximum, mean offset", "[face]") {
  site::EyeErrorStats stats;
  CHECK(stats.to_json()["median_mm"].is_null());
  const Eigen::Vector3d truth(0, 0.1, 0.6);
  for (int i = 1; i <= 20; ++i) stats.add(truth + Eigen::Vector3d(0, 0, 0.001 * i), truth);
  const nlohmann::json json = stats.to_json();
  CHECK(json["frames"] == 20);
  CHECK(json["median_mm"].get<double>() == Approx(10.5).margin(1.0));
  CHECK(json["p95_mm"].get<double>() == Approx(19.0).margin(1.0));
  CHECK(json["max_mm"].get<double>() == Approx(20.0));
  CHECK(json["mean_offset_mm"][2].get<double>() == Approx(10.5));
}
