// The camera model and its JSON: projection with distortion, rays back, and clear errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <opencv2/calib3d.hpp>

#include "config/json.h"
#include "geometry/camera.h"
#include "passes/common/ibr_scene.h"

using namespace rt;

namespace {

Camera test_camera_camera_model() {
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

// A wide-angle RGBD color camera with the full rational model, every coefficient non-zero and
// each a different value, of the size an Azure Kinect's factory calibration gives its 1280x720
// color camera (OpenCV's CALIB_RATIONAL_MODEL: k1-k6 near 1, p1 and p2 below 1e-3).
Camera rational_camera() {
  Camera camera = test_camera_camera_model();
  camera.name = "wide";
  camera.intrinsics = {1280, 720, 605.2, 604.8, 638.1, 367.4,
                       {.k1 = 0.52, .k2 = -2.71, .p1 = 6.1e-4, .p2 = -2.7e-4, .k3 = 1.62, .k4 = 0.40, .k5 = -2.53,
                        .k6 = 1.54}};
  return camera;
}

// The coefficients as OpenCV takes them, written out here in its documented order
// (k1, k2, p1, p2, k3, k4, k5, k6), not through Distortion::as_opencv().
std::vector<double> opencv_coefficients(const Distortion& d) { return {d.k1, d.k2, d.p1, d.p2, d.k3, d.k4, d.k5, d.k6}; }

cv::Matx33d opencv_camera_matrix(const CameraIntrinsics& k) { return {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}; }

// Site-frame points that the camera sees over its whole image, corners included: a grid of
// undistorted directions (x/z up to 1.05, y/z up to 0.6: the image corners and a little beyond) at depths
// from 0.4 to 2 m.
std::vector<Eigen::Vector3d> points_across_the_view(const Camera& camera) {
  std::vector<Eigen::Vector3d> points;
  const Eigen::Isometry3d site_from_camera = camera.camera_from_site.inverse();
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 8; ++j) {
      const double x = -1.05 + 0.21 * i, y = -0.6 + 0.15 * j, z = 0.4 + 0.16 * ((i + j) % 11);
      points.push_back(site_from_camera * Eigen::Vector3d(x * z, y * z, z));
    }
  return points;
}

// OpenCV's projection of the site points with the camera's pose as rvec, tvec.
std::vector<cv::Point2d> opencv_project(const Camera& camera, const std::vector<Eigen::Vector3d>& points) {
  std::vector<cv::Point3d> object;
  for (const auto& p : points) object.emplace_back(p.x(), p.y(), p.z());
  cv::Matx33d rotation;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation(r, c) = camera.camera_from_site.linear()(r, c);
  cv::Vec3d rvec;
  cv::Rodrigues(rotation, rvec);
  const Eigen::Vector3d t = camera.camera_from_site.translation();
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, rvec, cv::Vec3d(t.x(), t.y(), t.z()), opencv_camera_matrix(camera.intrinsics),
                    opencv_coefficients(camera.intrinsics.distortion), image);
  return image;
}

}  // namespace

// Tolerances against OpenCV. Camera::project and OpenCV both work in double: what differs is
// the pose (a matrix here, a Rodrigues vector there), worth about 1e-12 px. The shader's lens
// maths is float: about 1e-7 of pixel coordinates near 1000, through a dozen operations.
constexpr double kDoubleProjectionTolerancePx = 1e-9;
constexpr double kFloatProjectionTolerancePx = 2e-3;
// Undistortion is iterative, and OpenCV's undistortPoints stops after 5 iterations: with this
// lens that leaves at most 2.1e-8 rad at the image corners (1.3e-5 px at fx 605).
constexpr double kUndistortionToleranceRad = 1e-7;
// The depth rays' atlas stores x/z and y/z as float.
constexpr double kRayAtlasTolerancePx = 1e-3;

TEST_CASE("projection with the full rational model (k1-k6, p1, p2) is OpenCV's projectPoints", "[camera]") {
  const Camera camera = rational_camera();
  const auto points = points_across_the_view(camera);
  const auto expected = opencv_project(camera, points);
  double worst = 0;
  double left = 1e9, right = -1e9, top = 1e9, bottom = -1e9;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto pixel = camera.project(points[i]);
    REQUIRE(pixel);
    worst = std::max(worst, (*pixel - Eigen::Vector2d(expected[i].x, expected[i].y)).norm());
    left = std::min(left, pixel->x()), right = std::max(right, pixel->x());
    top = std::min(top, pixel->y()), bottom = std::max(bottom, pixel->y());
  }
  CHECK(worst < kDoubleProjectionTolerancePx);
  // The points cover the image, corners included (the distortion is largest there).
  CHECK(left < 10);
  CHECK(right > 1270);
  CHECK(top < 10);
  CHECK(bottom > 710);
  // Each coefficient moves the projection: a model that ignored one would fail above.
  const Eigen::Vector3d corner_point = points.front();
  const Eigen::Vector2d with_all = *camera.project(corner_point);
  for (double Distortion::*coefficient : {&Distortion::k1, &Distortion::k2, &Distortion::p1, &Distortion::p2,
                                          &Distortion::k3, &Distortion::k4, &Distortion::k5, &Distortion::k6}) {
    Camera without = camera;
    without.intrinsics.distortion.*coefficient = 0.0;
    CHECK((*without.project(corner_point) - with_all).norm() > 0.1);
  }
}

TEST_CASE("the shader's lens maths (passes/common/ibr_scene) is OpenCV's projectPoints in float", "[camera]") {
  const Camera camera = rational_camera();
  const std::vector<passes::IbrCameraModel> cameras{{camera, camera}};
  const passes::IbrSceneTable table = passes::make_scene_table(camera, cameras);
  const auto points = points_across_the_view(camera);
  const auto expected = opencv_project(camera, points);
  double worst = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const passes::Float3 site{float(points[i].x()), float(points[i].y()), float(points[i].z())};
    const passes::Float3 p = passes::transform_point(table.cameras[0].camera_from_site, site);
    const passes::Float2 pixel = passes::lens_project(table.cameras[0].color, p);
    worst = std::max(worst, std::hypot(pixel.x - expected[i].x, pixel.y - expected[i].y));
  }
  CHECK(worst < kFloatProjectionTolerancePx);
}

TEST_CASE("undistortion with the full rational model inverts OpenCV's projection", "[camera]") {
  const Camera camera = rational_camera();
  const auto points = points_across_the_view(camera);
  const auto pixels = opencv_project(camera, points);
  double worst = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d ray = camera.ray_in_site({pixels[i].x, pixels[i].y});
    const Eigen::Vector3d to_point = (points[i] - camera.position_in_site()).normalized();
    worst = std::max(worst, std::acos(std::clamp(ray.dot(to_point), -1.0, 1.0)));
  }
  INFO("worst angle between the ray and the point: " << worst << " rad");
  CHECK(worst < kUndistortionToleranceRad);

  // The depth cameras' per-pixel rays (passes/common/ibr_scene): OpenCV projects each ray back
  // onto its own pixel centre, over the whole image of a small depth camera with the same lens.
  Camera depth = camera;
  depth.intrinsics = scaled_intrinsics(camera.intrinsics, 0.05);  // 64x36
  const std::vector<passes::IbrCameraModel> cameras{{depth, depth}};
  const HostImage rays = passes::depth_ray_atlas(cameras);
  REQUIRE(rays.width == 64);
  REQUIRE(rays.height == 36);
  // The atlas holds the rays in the site frame: turned back into the camera's, at z = 1.
  const Eigen::Matrix3d camera_from_site = depth.camera_from_site.rotation();
  std::vector<cv::Point3d> directions;
  for (uint32_t y = 0; y < rays.height; ++y)
    for (uint32_t x = 0; x < rays.width; ++x) {
      REQUIRE(rays.at(x, y, 3) == 1.0f);
      const Eigen::Vector3d ray = camera_from_site * Eigen::Vector3d(rays.at(x, y, 0), rays.at(x, y, 1), rays.at(x, y, 2));
      REQUIRE(ray.z() == Approx(1.0).epsilon(1e-6));
      directions.emplace_back(ray.x() / ray.z(), ray.y() / ray.z(), 1.0);
    }
  std::vector<cv::Point2d> back;
  cv::projectPoints(directions, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), opencv_camera_matrix(depth.intrinsics),
                    opencv_coefficients(depth.intrinsics.distortion), back);
  double worst_px = 0;
  for (size_t i = 0; i < back.size(); ++i)
    worst_px = std::max(worst_px, std::hypot(back[i].x - double(i % rays.width), back[i].y - double(i / rays.width)));
  CHECK(worst_px < kRayAtlasTolerancePx);
}

TEST_CASE("a projected point's ray passes back through it", "[camera]") {
  const Camera camera = test_camera_camera_model();
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
  const Camera camera = test_camera_camera_model();
  CHECK_FALSE(camera.project(Eigen::Vector3d(-1.5, 0.9, -0.6)));
  CHECK_FALSE(camera.project(Eigen::Vector3d(std::nan(""), 0, 0.7)));
}

TEST_CASE("camera JSON round-trips with named fields", "[camera]") {
  const Camera camera = test_camera_camera_model();
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
  nlohmann::json json = camera_to_json(test_camera_camera_model());
  json.erase("fx");
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("camera 'top-left'") && Catch::Contains("'fx'"));
  json = camera_to_json(test_camera_camera_model());
  json["fy"] = "two hundred";
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("'fy' must be a number"));
  json = camera_to_json(test_camera_camera_model());
  json["width"] = -5;
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("'width' must be > 0"));
  json = camera_to_json(test_camera_camera_model());
  json["distortion"]["k9"] = 0.1;
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("unknown coefficient 'k9'"));
  json = camera_to_json(test_camera_camera_model());
  json["camera_from_site"][0][0] = 2.0;
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("not a rotation"));
  json = camera_to_json(test_camera_camera_model());
  json["camera_from_site"] = {1, 2, 3};
  CHECK_THROWS_WITH(camera_from_json(json), Catch::Contains("4x4"));
  CHECK_THROWS_WITH(config::read_json_file("/nonexistent/site.json"), Catch::Contains("/nonexistent/site.json"));
  const auto huge = std::filesystem::temp_directory_path() / ("remotetouch-huge-" + std::to_string(getpid()) + ".json");
  std::ofstream(huge) << "{\"fx\": 1E999}";
  CHECK_THROWS_AS(config::read_json_file(huge), config::JsonError);  // out of range: still a JsonError
  std::filesystem::remove(huge);
}
