// Triangulation of the viewer's eyes: rays to a point, calibrated pixels to a point, both eyes
// to a viewpoint; exact cases to sub-micrometre, noise, and every way it must refuse.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "viewer/eye_pair.h"
#include "viewer/multiview_point.h"
#include "viewer/ray_triangulation.h"
#include "viewer/simulated_views.h"

namespace {

// Exact rays meet exactly; what is left is double rounding of coordinates near 1 m (~1e-16 m)
// amplified by the solve. A micrometre is far above that and far below anything that matters.
constexpr double kExactToleranceM = 1e-6;

using rt::Ray;
using rt::ViewerFailure;

std::vector<Ray> rays_through(const Eigen::Vector3d& point, const std::vector<Eigen::Vector3d>& origins) {
  std::vector<Ray> rays;
  for (const Eigen::Vector3d& origin : origins) rays.push_back({origin, point - origin});
  return rays;
}

std::vector<Eigen::Vector3d> stand_origins() {
  std::vector<Eigen::Vector3d> origins;
  for (const rt::Camera& camera : rt::simulated_camera_stand()) origins.push_back(camera.position_in_site());
  return origins;
}

// Sum of squared distances to the rays: the quantity the solver minimises.
double cost(const std::vector<Ray>& rays, const Eigen::Vector3d& point) {
  double sum = 0;
  for (const Ray& ray : rays) {
    const Eigen::Vector3d d = ray.direction.normalized();
    const Eigen::Vector3d offset = point - ray.origin;
    sum += (offset - offset.dot(d) * d).squaredNorm();
  }
  return sum;
}

Eigen::Vector3d rotated(const Eigen::Vector3d& direction, double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()) * direction;
}

}  // namespace

TEST_CASE("exact rays from 2 to 6 views meet at the point to sub-micrometre", "[viewer][triangulation]") {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> lateral(-0.3, 0.3), depth(0.4, 1.2);
  const std::vector<Eigen::Vector3d> all = stand_origins();
  for (size_t views = 2; views <= all.size(); ++views) {
    const std::vector<Eigen::Vector3d> origins(all.begin(), all.begin() + std::ptrdiff_t(views));
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::Vector3d truth(lateral(random), lateral(random), depth(random));
      const rt::PointEstimate estimate = rt::nearest_point_to_rays(rays_through(truth, origins));
      INFO("views " << views << " truth " << truth.transpose() << ": " << estimate.message);
      REQUIRE(estimate.ok());
      CHECK((estimate.point - truth).norm() < kExactToleranceM);
      CHECK(estimate.rms_ray_distance_m < kExactToleranceM);
    }
  }
}

TEST_CASE("noisy rays give the least-squares point, with an error of the noise's size", "[viewer][triangulation]") {
  std::mt19937 random(11);
  std::normal_distribution<double> noise_rad(0.0, 0.001);  // 1 mrad: about 1 px at fx = 1000
  const std::vector<Eigen::Vector3d> origins = stand_origins();
  const Eigen::Vector3d truth(0.05, -0.02, 0.7);
  double worst_error = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<Ray> rays = rays_through(truth, origins);
    for (Ray& ray : rays)
      ray.direction = rotated(rotated(ray.direction, noise_rad(random), Eigen::Vector3d::UnitX()), noise_rad(random),
                              Eigen::Vector3d::UnitY());
    const rt::PointEstimate estimate = rt::nearest_point_to_rays(rays);
    REQUIRE(estimate.ok());
    REQUIRE(estimate.point.allFinite());
    worst_error = std::max(worst_error, (estimate.point - truth).norm());
    // Optimality: any small step away increases the summed squared ray distance.
    for (int axis = 0; axis < 3; ++axis)
      for (double step : {-1e-4, 1e-4}) {
        Eigen::Vector3d moved = estimate.point;
        moved[axis] += step;
        CHECK(cost(rays, moved) > cost(rays, estimate.point));
      }
    // The rays miss each other by about the noise times the distance (1 mrad * 0.8 m).
    CHECK(estimate.rms_ray_distance_m > 1e-5);
    CHECK(estimate.rms_ray_distance_m < 3e-3);
  }
  // Six rays of 1 mrad noise at ~0.8 m: each misses by ~0.8 mm; the solution averages them.
  CHECK(worst_error < 3e-3);
}

TEST_CASE("fewer than two rays is a clear error", "[viewer][triangulation]") {
  const std::vector<Ray> none;
  const rt::PointEstimate zero = rt::nearest_point_to_rays(none);
  CHECK(zero.failure == ViewerFailure::TooFewViews);
  const std::vector<Ray> one = {{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1)}};
  const rt::PointEstimate single = rt::nearest_point_to_rays(one);
  CHECK(single.failure == ViewerFailure::TooFewViews);
  CHECK_THAT(single.message, Catch::Contains("at least 2") && Catch::Contains("got 1"));
  CHECK(single.point.allFinite());
}

TEST_CASE("near-parallel and parallel rays are refused, never a NaN", "[viewer][triangulation]") {
  const Eigen::Vector3d a(-0.01, 0, 0), b(0.01, 0, 0);
  SECTION("exactly parallel") {
    const std::vector<Ray> rays = {{a, {0, 0, 1}}, {b, {0, 0, 1}}};
    const rt::PointEstimate estimate = rt::nearest_point_to_rays(rays);
    CHECK(estimate.failure == ViewerFailure::RaysNearlyParallel);
    CHECK(estimate.point.allFinite());
  }
  SECTION("1 degree apart, below the 2-degree limit") {
    const Eigen::Vector3d tilted = rotated({0, 0, 1}, -1.0 * std::numbers::pi / 180, Eigen::Vector3d::UnitY());
    const std::vector<Ray> rays = {{a, {0, 0, 1}}, {b, tilted}};
    const rt::PointEstimate estimate = rt::nearest_point_to_rays(rays);
    CHECK(estimate.failure == ViewerFailure::RaysNearlyParallel);
    CHECK_THAT(estimate.message, Catch::Contains("nearly parallel"));
    // The same rays pass once the limit allows them: the refusal is the limit, not the solver.
    rt::RayTriangulationLimits loose;
    loose.min_ray_angle_deg = 0.5;
    const rt::PointEstimate allowed = rt::nearest_point_to_rays(rays, loose);
    REQUIRE(allowed.ok());
    CHECK(allowed.point.z() > 1.0);  // 2 cm apart, 1 degree: they meet ~1.15 m out
  }
  SECTION("many rays, all within a hair of each other") {
    std::vector<Ray> rays;
    for (int i = 0; i < 5; ++i) rays.push_back({Eigen::Vector3d(0.001 * i, 0, 0), rotated({0, 0, 1}, 1e-4 * i, Eigen::Vector3d::UnitY())});
    CHECK(rt::nearest_point_to_rays(rays).failure == ViewerFailure::RaysNearlyParallel);
  }
}

TEST_CASE("rays that meet behind their cameras are refused, naming the ray", "[viewer][triangulation]") {
  // Two cameras facing +z whose rays diverge: their lines cross at z = -0.1, behind both.
  const std::vector<Ray> rays = {{{-0.1, 0, 0}, {-1, 0, 1}}, {{0.1, 0, 0}, {1, 0, 1}}};
  const rt::PointEstimate estimate = rt::nearest_point_to_rays(rays);
  CHECK(estimate.failure == ViewerFailure::BehindCamera);
  CHECK(estimate.offending_ray == 0);
  CHECK_THAT(estimate.message, Catch::Contains("behind"));
}

TEST_CASE("rays holding NaN or a zero direction are invalid input", "[viewer][triangulation]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Ray> with_nan = {{{0, 0, 0}, {0, 0, 1}}, {{nan, 0, 0}, {0, 0, 1}}};
  const rt::PointEstimate a = rt::nearest_point_to_rays(with_nan);
  CHECK(a.failure == ViewerFailure::InvalidInput);
  CHECK(a.offending_ray == 1);
  const std::vector<Ray> zero = {{{0, 0, 0}, {0, 0, 1}}, {{1, 0, 0}, {0, 0, 0}}};
  CHECK(rt::nearest_point_to_rays(zero).failure == ViewerFailure::InvalidInput);
}

namespace {

rt::Distortion mild_lens_viewer_triangulation() {
  // Typical of an RGBD color camera: a little barrel distortion, tiny tangential terms.
  rt::Distortion d;
  d.k1 = -0.08;
  d.k2 = 0.03;
  d.p1 = 0.0005;
  d.p2 = -0.0003;
  return d;
}

std::vector<rt::Camera> stand(bool distorted) {
  rt::CameraStandOptions options;
  options.intrinsics = {1280, 720, 640.0, 640.0, 639.5, 359.5, {}};
  if (distorted) options.intrinsics.distortion = mild_lens_viewer_triangulation();
  return rt::simulated_camera_stand(options);
}

std::vector<rt::PixelObservation> observe(const std::vector<rt::Camera>& cameras, const Eigen::Vector3d& point,
                                          const std::vector<size_t>& which) {
  std::vector<rt::PixelObservation> observations;
  for (size_t index : which) {
    const auto pixel = cameras[index].project(point);
    REQUIRE(pixel);
    observations.push_back({index, *pixel});
  }
  return observations;
}

}  // namespace

TEST_CASE("calibrated pixels triangulate through the camera model", "[viewer][triangulation]") {
  const Eigen::Vector3d truth(0.04, 0.03, 0.68);
  SECTION("pinhole cameras: sub-micrometre") {
    const auto cameras = stand(false);
    const rt::MultiViewPoint point = rt::triangulate_observations(cameras, observe(cameras, truth, {0, 1, 2, 3, 4, 5}));
    INFO(point.message);
    REQUIRE(point.ok());
    CHECK((point.point - truth).norm() < kExactToleranceM);
    CHECK(point.max_reprojection_px < 1e-6);
    CHECK(point.cameras_used.size() == 6);
  }
  SECTION("distorted cameras: the pixels are undistorted, not used as pinhole pixels") {
    const auto cameras = stand(true);
    // Off to the side, where the lens displaces pixels by a few pixels (near the image centre
    // it displaces them by hundredths, and ignoring it would go unnoticed).
    const Eigen::Vector3d truth(0.3, 0.2, 0.6);
    const auto observations = observe(cameras, truth, {1, 4, 2});
    const rt::MultiViewPoint point = rt::triangulate_observations(cameras, observations);
    INFO(point.message);
    REQUIRE(point.ok());
    // OpenCV's undistortPoints iterates a fixed five times; for this lens its round trip is
    // within 1e-5 px over the whole image (1e-6 px in the middle), so sub-micrometre still holds.
    CHECK((point.point - truth).norm() < kExactToleranceM);
    // Ignoring the distortion would be off by millimetres: the model is doing real work.
    auto pinhole = cameras;
    for (rt::Camera& camera : pinhole) camera.intrinsics.distortion = {};
    const rt::MultiViewPoint naive = rt::triangulate_observations(pinhole, observations);
    CHECK((!naive.ok() || (naive.point - truth).norm() > 1e-3));
  }
}

TEST_CASE("a wrong detection in one of several views is dropped", "[viewer][triangulation]") {
  const auto cameras = stand(false);
  const Eigen::Vector3d truth(-0.03, 0.02, 0.72);
  auto observations = observe(cameras, truth, {0, 1, 4, 5});
  observations[2].pixel += Eigen::Vector2d(25, -12);  // bottom-centre picked an eyebrow
  const rt::MultiViewPoint point = rt::triangulate_observations(cameras, observations);
  INFO(point.message);
  REQUIRE(point.ok());
  CHECK(point.cameras_rejected == std::vector<size_t>{4});
  CHECK((point.point - truth).norm() < kExactToleranceM);

  SECTION("with two views there is no majority: a clear error naming both cameras") {
    auto two = observe(cameras, truth, {1, 4});
    two[0].pixel += Eigen::Vector2d(30, 0);  // across the vertical baseline: not epipolar
    const rt::MultiViewPoint refused = rt::triangulate_observations(cameras, two);
    CHECK(refused.failure == ViewerFailure::ReprojectionTooLarge);
    CHECK_THAT(refused.message, Catch::Contains("top-centre") && Catch::Contains("bottom-centre"));
    CHECK(refused.point.allFinite());
  }
}

TEST_CASE("a point on, behind or at the screen plane is refused", "[viewer][triangulation]") {
  // Cameras well in front of the screen looking back at it can see points at z <= 0.
  const rt::CameraIntrinsics k{640, 360, 320.0, 320.0, 319.5, 179.5, {}};
  const std::vector<rt::Camera> cameras = {
      rt::camera_looking_at("front-left", k, {-0.3, 0.1, 0.6}, {0, 0, -0.1}),
      rt::camera_looking_at("front-right", k, {0.3, 0.1, 0.6}, {0, 0, -0.1}),
  };
  // 2 cm is in front of the glass but closer than any eye can be: refused by the 5 cm limit.
  for (double z : {0.02, 0.0, -0.05}) {
    const rt::MultiViewPoint point = rt::triangulate_observations(cameras, observe(cameras, {0.02, 0.01, z}, {0, 1}));
    INFO("z = " << z);
    CHECK(point.failure == ViewerFailure::NotInFrontOfScreen);
    CHECK_THAT(point.message, Catch::Contains("in front of the screen"));
    CHECK(point.point.allFinite());
  }
  const rt::MultiViewPoint in_front = rt::triangulate_observations(cameras, observe(cameras, {0.02, 0.01, 0.1}, {0, 1}));
  CHECK(in_front.ok());
}

TEST_CASE("pixels whose rays meet behind the cameras are refused, naming a camera", "[viewer][triangulation]") {
  // Two cameras looking straight out of the screen; the left one's ray through its image's right
  // edge heads to -x, the right one's through its left edge to +x: the lines cross behind both.
  const rt::CameraIntrinsics k{640, 360, 320.0, 320.0, 319.5, 179.5, {}};
  const std::vector<rt::Camera> cameras = {
      rt::camera_looking_at("left", k, {-0.2, 0, 0.03}, {-0.2, 0, 1}),
      rt::camera_looking_at("right", k, {0.2, 0, 0.03}, {0.2, 0, 1}),
  };
  const std::vector<rt::PixelObservation> observations = {{0, {639, 179.5}}, {1, {0, 179.5}}};
  const rt::MultiViewPoint point = rt::triangulate_observations(cameras, observations);
  CHECK(point.failure == ViewerFailure::BehindCamera);
  CHECK_THAT(point.message, Catch::Contains("camera 'left'"));
  CHECK(point.point.allFinite());
}

TEST_CASE("bad observations are invalid input with a message saying which", "[viewer][triangulation]") {
  const auto cameras = stand(false);
  const Eigen::Vector3d truth(0, 0, 0.7);
  auto good = observe(cameras, truth, {1, 4});

  auto out_of_range = good;
  out_of_range[1].camera_index = 9;
  CHECK_THAT(rt::triangulate_observations(cameras, out_of_range).message, Catch::Contains("only 6 cameras"));

  auto duplicate = good;
  duplicate[1].camera_index = 1;
  CHECK_THAT(rt::triangulate_observations(cameras, duplicate).message, Catch::Contains("more than one observation"));

  auto not_a_number = good;
  not_a_number[0].pixel.x() = std::numeric_limits<double>::quiet_NaN();
  const rt::MultiViewPoint nan_result = rt::triangulate_observations(cameras, not_a_number);
  CHECK(nan_result.failure == ViewerFailure::InvalidInput);
  CHECK(nan_result.point.allFinite());

  auto outside = good;
  outside[0].pixel = {1500, 100};
  CHECK_THAT(rt::triangulate_observations(cameras, outside).message, Catch::Contains("outside the 1280x720 image"));

  const rt::MultiViewPoint single = rt::triangulate_observations(cameras, std::vector<rt::PixelObservation>{good[0]});
  CHECK(single.failure == ViewerFailure::TooFewViews);
  CHECK_THAT(single.message, Catch::Contains("top-centre"));
}

namespace {

// A viewer's eyes 63 mm apart (the adult mean), head at `centre`, facing the screen.
struct TrueEyes {
  Eigen::Vector3d right, left;
};
TrueEyes eyes_at_viewer_triangulation(const Eigen::Vector3d& centre) {
  return {centre + Eigen::Vector3d(0.0315, 0, 0), centre - Eigen::Vector3d(0.0315, 0, 0)};
}

std::vector<rt::ViewEyes> view_eyes(const std::vector<rt::Camera>& cameras, const TrueEyes& eyes, const std::vector<size_t>& which) {
  std::vector<rt::ViewEyes> views;
  for (size_t index : which) {
    const auto right = cameras[index].project(eyes.right);
    const auto left = cameras[index].project(eyes.left);
    REQUIRE((right && left));
    views.push_back({index, {*right, *left}});
  }
  return views;
}

}  // namespace

TEST_CASE("which eye is the viewer's right follows from the camera's pose", "[viewer][eyes]") {
  const auto cameras = stand(true);
  const TrueEyes eyes = eyes_at_viewer_triangulation({0.05, 0.02, 0.7});
  for (const rt::Camera& upright : cameras) {
    // The same camera turned upside down on its mount: the image flips, the answer must not.
    rt::Camera upside_down = upright;
    upside_down.name += " upside down";
    upside_down.camera_from_site = Eigen::Isometry3d(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ())) * upright.camera_from_site;
    for (const rt::Camera* camera : std::array<const rt::Camera*, 2>{&upright, &upside_down}) {
      const Eigen::Vector2d right = *camera->project(eyes.right), left = *camera->project(eyes.left);
      INFO(camera->name);
      for (bool swap : {false, true}) {
        const auto labelled = swap ? rt::assign_viewer_sides(*camera, left, right) : rt::assign_viewer_sides(*camera, right, left);
        REQUIRE(labelled);
        CHECK((labelled->viewer_right - right).norm() < 1e-12);
        CHECK((labelled->viewer_left - left).norm() < 1e-12);
      }
    }
  }
  // An upright camera facing the viewer shows the viewer's right eye on the image's left.
  const Eigen::Vector2d right = *cameras[1].project(eyes.right), left = *cameras[1].project(eyes.left);
  CHECK(right.x() < left.x());
  CHECK_FALSE(rt::assign_viewer_sides(cameras[1], right, right));
}

TEST_CASE("both eyes triangulate and the viewpoint is their midpoint", "[viewer][eyes]") {
  const auto cameras = stand(true);
  const Eigen::Vector3d centre(-0.08, 0.04, 0.66);
  const TrueEyes eyes = eyes_at_viewer_triangulation(centre);
  const rt::EyePair pair = rt::triangulate_eye_pair(cameras, view_eyes(cameras, eyes, {1, 2, 4, 5}));
  INFO(pair.message);
  REQUIRE(pair.ok());
  CHECK((pair.midpoint - centre).norm() < 1e-5);
  CHECK((pair.viewer_right - eyes.right).norm() < 1e-5);
  CHECK((pair.viewer_left - eyes.left).norm() < 1e-5);
  CHECK(pair.cameras_seeing_eyes.size() == 4);

  SECTION("one view with its eyes swapped is outvoted") {
    auto views = view_eyes(cameras, eyes, {1, 2, 4, 5});
    std::swap(views[1].eyes.viewer_right, views[1].eyes.viewer_left);
    const rt::EyePair outvoted = rt::triangulate_eye_pair(cameras, views);
    INFO(outvoted.message);
    REQUIRE(outvoted.ok());
    CHECK(outvoted.cameras_rejected == std::vector<size_t>{2});
    CHECK((outvoted.midpoint - centre).norm() < 1e-5);
  }
  SECTION("with two views, swapped labels are refused") {
    auto views = view_eyes(cameras, eyes, {1, 4});
    std::swap(views[0].eyes.viewer_right, views[0].eyes.viewer_left);
    const rt::EyePair refused = rt::triangulate_eye_pair(cameras, views);
    CHECK_FALSE(refused.ok());
    CHECK(refused.midpoint.allFinite());
  }
  SECTION("eyes 15 cm apart are not one person's") {
    const TrueEyes wide{centre + Eigen::Vector3d(0.075, 0, 0), centre - Eigen::Vector3d(0.075, 0, 0)};
    const rt::EyePair refused = rt::triangulate_eye_pair(cameras, view_eyes(cameras, wide, {1, 4}));
    CHECK(refused.failure == ViewerFailure::EyesImplausible);
    CHECK_THAT(refused.message, Catch::Contains("150") && Catch::Contains("mm apart"));
  }
  SECTION("a single view is a clear error") {
    const rt::EyePair refused = rt::triangulate_eye_pair(cameras, view_eyes(cameras, eyes, {2}));
    CHECK(refused.failure == ViewerFailure::TooFewViews);
    CHECK_THAT(refused.message, Catch::Contains("top-right"));
  }
}
