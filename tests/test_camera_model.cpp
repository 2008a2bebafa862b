// The camera model and its JSON: projection with distortion, rays back, and clear errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "config/json.h"
#include "geometry/camera.h"

using namespace rt;

namespace {

Camera test_camera() {
  Camera camera;
  camera.name = "top-left";
  camera.intrinsics = {512, 512, 250.0, 251.0, 255.5, 254.0, {0.1, -0.05, 0.001, -0.0005, 0.01, 0, 0, 0}};
  // At (-0.7, 0.45, 0.05) in the site frame, looking at the seat (0, 0, 0.7).
  const Eigen::Vector3d position(-0.7, 0.45, 0.05), target(0, 0, 0.7);
  const Eigen::Vector3d forward = (target - position).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d site_from_camera;
  site_from_camera << right, down, forward;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = site_from_camera;
  pose.translation() = position;
  camera.camera_from_site = pose.inverse();
  return camera;
}

}  // namespace

TEST_CASE("a projected point's ray passes back through it", "[camera]") {
  const Camera camera = test_camera();
  CHECK((camera.position_in_site() - Eigen::Vector3d(-0.7, 0.45, 0.05)).norm() < 1e-12);
  for (const Eigen::Vector3d& point : {Eigen::Vector3d(0, 0, 0.7), Eigen::Vector3d(0.1, -0.2, 0.5),
                                       Eigen::Vector3d(-0.3, 0.3, 0.9)}) {
    const auto pixel = camera.project(point);
    REQUIRE(pixel);
    const Eigen::Vector3d ray = camera.ray_in_site(*pixel);
    const Eigen::Vector3d to_point = (point - camera.position_in_site()).normalized();
    CHECK((ray - to_point).norm() < 1e-6);  // undistortion is iterative in OpenCV
  }
}

TEST_CASE("points behind the camera do not project", "[camera]") {
  const Camera camera = test_camera();
  CHECK_FALSE(camera.project(Eigen::Vector3d(-1.5, 0.9, -0.6)));
  CHECK_FALSE(camera.project(Eigen::Vector3d(std::nan(""), 0, 0.7)));
}

TEST_CASE("camera JSON round-trips with named fields", "[camera]") {
  const Camera camera = test_camera();
  const nlohmann::json json = camera_to_json(camera);
  CHECK(json.at("fx").get<double>() == 250.0);
  CHECK(json.at("distortion").at("p2").get<double>() == -0.0005);
  const Camera back = camera_from_json(json);
  CHECK(back.name == "top-left");
  CHECK(back.intrinsics.cy == 254.0);
  CHECK(back.intrinsics.distortion.k3 == 0.01);
  CHECK((back.camera_from_site.matrix() - camera.camera_from_site.matrix()).norm() < 1e-12);
}

TEST_CASE("bad camera JSON names the camera and the field", "[camera]") {
  nlohmann::json json = camera_to_json(test_camera());
  json.erase("fx");
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("camera 'top-left'") && Catch::Contains("'fx'"));
  json = camera_to_json(test_camera());
  json["fy"] = "two hundred";
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("'fy' must be a number"));
  json = camera_to_json(test_camera());
  json["width"] = -5;
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("'width' must be > 0"));
  json = camera_to_json(test_camera());
  json["distortion"]["k9"] = 0.1;
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("unknown coefficient 'k9'"));
  json = camera_to_json(test_camera());
  json["camera_from_site"][0][0] = 2.0;
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("not a rotation"));
  json = camera_to_json(test_camera());
  json["camera_from_site"] = {1, 2, 3};
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("4x4"));
  CHECK_THROWS_WITH(config::read_json_file("/nonexistent/site.json"), Catch::Contains("/nonexistent/site.json"));
  const auto huge = std::filesystem::temp_directory_path() / ("remotetouch-huge-" + std::to_string(getpid()) + ".json");
  std::ofstream(huge) << "{\"fx\": 1E999}";
  CHECK_THROWS_AS(config::read_json_file(huge), config::JsonError);  // out of range: still a JsonError
  std::filesystem::remove(huge);
}
