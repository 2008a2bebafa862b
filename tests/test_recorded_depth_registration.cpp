// A recorded site's cameras made fit for the image-based model
// (pipeline/recorded_depth_registration.h): a camera whose colour lens is apart from its depth
// lens gets the depth_in_color pass's output (against its C++ reference) and a model whose depth
// camera is its colour camera; an aligned camera is left untouched.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "passes/depth_in_color.h"
#include "pipeline/recorded_depth_registration.h"
#include "support/gpu_test.h"

using namespace rt;

namespace {

CameraIntrinsics intrinsics(uint32_t width, uint32_t height, double focal) {
  CameraIntrinsics camera;
  camera.width = width, camera.height = height;
  camera.fx = camera.fy = focal;
  camera.cx = (width - 1) / 2.0, camera.cy = (height - 1) / 2.0;
  return camera;
}

// A slanted surface about a metre away, with holes (no measurement).
HostImage slanted_depth(uint32_t width, uint32_t height) {
  HostImage depth(width, height, PixelFormat::R16U);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) depth.at(x, y) = (x * 7 + y * 3) % 23 == 0 ? 0.0f : float(900 + 2 * x + y);
  return depth;
}

}  // namespace

TEST_CASE("recorded depth registration: an offset camera gets depth in colour, an aligned one is untouched") {
  sim::RecordedRgbdSource::RecordedIntrinsics aligned{intrinsics(64, 36, 50), intrinsics(32, 29, 26)};
  sim::RecordedRgbdSource::RecordedIntrinsics offset{intrinsics(61, 37, 48), intrinsics(33, 27, 25)};
  offset.color_from_depth.translation() = Eigen::Vector3d(-0.032, -0.002, 0.004);
  pipeline::RecordedDepthRegistration registration(test::gpu(), {aligned, offset});
  CHECK(registration.registered_count() == 1);

  const Camera color0{"c0", aligned.color, Eigen::Isometry3d::Identity()}, depth0{"d0", aligned.depth, Eigen::Isometry3d::Identity()};
  const Camera color1{"c1", offset.color, Eigen::Isometry3d::Identity()}, depth1{"d1", offset.depth, Eigen::Isometry3d::Identity()};
  const std::vector<passes::IbrCameraModel> models = registration.models({{color0, depth0}, {color1, depth1}});
  CHECK(models[0].depth.intrinsics.width == 32);  // aligned: as recorded
  CHECK(models[1].depth.intrinsics.width == 61);  // registered: the colour camera
  CHECK(models[1].depth.intrinsics.fx == 48);

  std::vector<sim::RgbdImage> cameras(2);
  cameras[0].depth_mm = slanted_depth(32, 29);
  cameras[1].depth_mm = slanted_depth(33, 27);
  const HostImage untouched = cameras[0].depth_mm;
  registration.apply(cameras);
  CHECK(cameras[0].depth_mm.texels == untouched.texels);
  REQUIRE(cameras[1].depth_mm.width == 61);
  REQUIRE(cameras[1].depth_mm.height == 37);
  // The pass's own tolerance against its reference: 1 mm, and 0.1 % of the pixels + 2 may differ
  // where a pixel centre sits on a triangle's edge.
  const std::vector<float> rays = passes::depth_in_color_rays(offset.depth);
  const HostImage reference = passes::depth_in_color_reference(
      slanted_depth(33, 27), rays, passes::depth_in_color_params(offset.color, offset.color_from_depth));
  size_t differing = 0, covered = 0;
  for (size_t i = 0; i < reference.texels.size(); ++i) {
    const float gpu = cameras[1].depth_mm.texels[i];
    REQUIRE(std::isfinite(gpu));
    covered += gpu > 0;
    differing += std::abs(gpu - reference.texels[i]) > 1.0f;
  }
  CHECK(covered > reference.texels.size() / 2);
  CHECK(differing <= reference.texels.size() / 1000 + 2);
  CHECK(std::isfinite(registration.median_ms()));
  pipeline::RecordedDepthRegistration none(test::gpu(), {aligned});
  CHECK(none.registered_count() == 0);
  CHECK(none.median_ms() == 0.0);  // nothing registered: no time, not an average over no camera

  std::vector<sim::RgbdImage> wrong(3);
  CHECK_THROWS_WITH(registration.apply(wrong), Catch::Matchers::Contains("3 cameras for 2"));
}

TEST_CASE("recorded depth registration: a real camera's flying pixels are removed before its depth is registered") {
  // A wall at 1.2 m, and three pixels floating at half a metre: an L of mixed returns, which the
  // registration alone draws (they make one triangle of three on one surface) and which have two
  // neighbours on their surface each, fewer than depth_outliers keeps.
  sim::RecordedRgbdSource::RecordedIntrinsics offset{intrinsics(61, 37, 48), intrinsics(33, 27, 25)};
  offset.color_from_depth.translation() = Eigen::Vector3d(-0.032, -0.002, 0.004);
  HostImage depth(33, 27, PixelFormat::R16U, 1200.0f);
  depth.at(15, 12) = 500.0f, depth.at(16, 12) = 505.0f, depth.at(15, 13) = 510.0f;
  auto nearest_mm = [](const HostImage& image) {
    float nearest = 1e9f;
    for (const float v : image.texels)
      if (v > 0.0f) nearest = std::min(nearest, v);
    return nearest;
  };
  // Without the filter the floating pixels reach the colour image: the input bites.
  pipeline::DepthRegistration unfiltered(test::gpu(), offset.depth, offset.color, offset.color_from_depth);
  REQUIRE(nearest_mm(unfiltered.run(depth)) < 600.0f);

  pipeline::RecordedDepthRegistration registration(test::gpu(), {offset});
  std::vector<sim::RgbdImage> cameras(1);
  cameras[0].depth_mm = depth;
  registration.apply(cameras);
  const HostImage& registered = cameras[0].depth_mm;
  CHECK(nearest_mm(registered) > 1100.0f);
  // The wall is still there: most of the colour image sees it.
  size_t covered = 0;
  for (const float v : registered.texels) covered += v > 0.0f;
  CHECK(covered > registered.texels.size() / 2);
}
