// depth_in_color pass: GPU against the C++ reference on random cameras and scenes of odd sizes,
// and the hard cases. Tolerances: a pixel may differ by 1 mm (a z that rounds at half a
// millimetre); beyond that, at most 0.1% of the colour pixels + 2, each a pixel centre within
// float rounding of a triangle's edge, which GPU and reference may put on either side (at a depth
// edge that decides which surface covers it). No NaN or Inf, and none of these hold a hole.
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "passes/depth_in_color.h"
#include "pipeline/depth_registration.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::DepthInColorSettings;

namespace {

struct Rig {
  CameraIntrinsics depth, color;
  Eigen::Isometry3d color_from_depth = Eigen::Isometry3d::Identity();
};

HostImage run_gpu_depth_in_color(const HostImage& depth_mm, const Rig& rig, const DepthInColorSettings& settings = {}) {
  const passes::DepthInColorPass pass(test::gpu(), settings);
  const std::vector<float> rays = passes::depth_in_color_rays(rig.depth);
  const auto params = passes::depth_in_color_params(rig.color, rig.color_from_depth);
  test::PassHarness gpu("depth_in_color");
  pass.add_to(gpu.graph(), gpu.input("depth mm", depth_mm),
              gpu.buffer(passes::depth_in_color_rays_desc(depth_mm.width, depth_mm.height), std::as_bytes(std::span(rays))),
              gpu.buffer(passes::depth_in_color_nearest_desc(rig.color.width, rig.color.height)),
              gpu.output("depth in color", rig.color.width, rig.color.height, PixelFormat::R16U), [params] { return params; });
  return gpu.run().image("depth in color");
}

HostImage reference(const HostImage& depth_mm, const Rig& rig, const DepthInColorSettings& settings = {}) {
  return passes::depth_in_color_reference(depth_mm, passes::depth_in_color_rays(rig.depth),
                                          passes::depth_in_color_params(rig.color, rig.color_from_depth), settings);
}

// GPU and reference agree within the stated tolerances, and the GPU's result is finite.
void require_agrees(const HostImage& gpu, const HostImage& ref) {
  RT_REQUIRE_MOSTLY_MATCHES(gpu, ref, 1.0, 0.0, 0.001 * double(ref.width * ref.height) + 2);
}

CameraIntrinsics lens(std::mt19937& rng, uint32_t width, uint32_t height, double fov_scale) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = fov_scale * std::max(width, height) * (0.8 + 0.1 * unit(rng));
  k.fy = k.fx * (1.0 + 0.01 * unit(rng));
  k.cx = (width - 1) / 2.0 + 0.02 * width * unit(rng);
  k.cy = (height - 1) / 2.0 + 0.02 * height * unit(rng);
  // Mild, as the k4a's lenses are once the rational terms are in; strong enough that a p1/p2
  // swap or a missing term would move points by pixels.
  k.distortion = {.k1 = 0.1 * unit(rng), .k2 = 0.05 * unit(rng), .p1 = 0.002 * unit(rng), .p2 = 0.002 * unit(rng),
                  .k3 = 0.01 * unit(rng), .k4 = 0.05 * unit(rng), .k5 = 0.02 * unit(rng), .k6 = 0.005 * unit(rng)};
  return k;
}

// A colour camera beside the depth camera, as on an Azure Kinect (32 mm, a degree or two).
Rig random_rig(std::mt19937& rng, uint32_t dw, uint32_t dh, uint32_t cw, uint32_t ch) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Rig rig{lens(rng, dw, dh, 1.0), lens(rng, cw, ch, 1.1)};
  rig.color_from_depth = Eigen::Translation3d(-0.032 + 0.002 * unit(rng), 0.002 * unit(rng), 0.004 * unit(rng)) *
                         Eigen::AngleAxisd(0.03 * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), 1.0).normalized());
  return rig;
}

// A slanted wall at about 2.2 m, a body-like blob at about 1 m (unless `continuous`), a few
// holes, millimetre noise.
HostImage scene(std::mt19937& rng, uint32_t w, uint32_t h, float holes = 0.03f, bool continuous = false) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  HostImage depth(w, h, PixelFormat::R16U);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const float fx = (x + 0.5f) / float(w), fy = (y + 0.5f) / float(h);
      float mm = 2200.0f + 400.0f * (fx - 0.5f) + 100.0f * fy;
      const float r = std::hypot(fx - 0.45f, fy - 0.55f);
      if (r < 0.25f && !continuous) mm = 1000.0f + 600.0f * r * r;
      if (continuous) mm += 150.0f * std::sin(6.0f * fx) * std::cos(5.0f * fy);
      mm = std::floor(mm + 3.0f * unit(rng));
      depth.at(x, y) = unit(rng) < holes ? 0.0f : mm;
    }
  return depth;
}

size_t nonzero(const HostImage& image) {
  return size_t(std::count_if(image.texels.begin(), image.texels.end(), [](float v) { return v != 0.0f; }));
}

// Zero pixels with nonzero ones on both sides along their row and along their column.
size_t holes(const HostImage& image) {
  const int w = int(image.width), h = int(image.height);
  std::vector<int> row_first(size_t(h), w), row_last(size_t(h), -1), column_first(size_t(w), h), column_last(size_t(w), -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (image.at(uint32_t(x), uint32_t(y)) != 0.0f) {
        row_first[size_t(y)] = std::min(row_first[size_t(y)], x), row_last[size_t(y)] = x;
        column_first[size_t(x)] = std::min(column_first[size_t(x)], y), column_last[size_t(x)] = y;
      }
  size_t count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (image.at(uint32_t(x), uint32_t(y)) == 0.0f && x > row_first[size_t(y)] && x < row_last[size_t(y)] &&
          y > column_first[size_t(x)] && y < column_last[size_t(x)])
        ++count;
  return count;
}

}  // namespace

TEST_CASE("depth_in_color matches the reference on random cameras and scenes of odd sizes", "[depth_in_color][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(47);
  for (const auto& [dw, dh] : test::odd_sizes()) {
    // Colour larger than depth, as on the device (720p colour over 640x576 or 320x288 depth).
    const uint32_t cw = 2 * dw + 3, ch = 2 * dh + 1;
    INFO("depth " << dw << "x" << dh << ", colour " << cw << "x" << ch);
    const Rig rig = random_rig(rng, dw, dh, cw, ch);
    const HostImage depth = scene(rng, dw, dh);
    const HostImage gpu = run_gpu_depth_in_color(depth, rig), ref = reference(depth, rig);
    require_agrees(gpu, ref);
    if (dw < 2 || dh < 2) CHECK(nonzero(ref) == 0);  // a single row or column spans no area
    if (dw >= 33 && dh >= 17) CHECK(nonzero(ref) > ref.texels.size() / 4);
  }
}

TEST_CASE("depth_in_color upsampled four times leaves no holes in a continuous surface", "[depth_in_color][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(48);
  const uint32_t dw = 81, dh = 73, cw = 4 * dw, ch = 4 * dh;
  Rig rig = random_rig(rng, dw, dh, cw, ch);
  const HostImage depth = scene(rng, dw, dh, 0.0f, true);
  const HostImage gpu = run_gpu_depth_in_color(depth, rig), ref = reference(depth, rig);
  require_agrees(gpu, ref);
  CHECK(holes(ref) == 0);
  CHECK(holes(gpu) == 0);
  CHECK(nonzero(gpu) > gpu.texels.size() / 2);
}

TEST_CASE("depth_in_color hard cases", "[depth_in_color][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(49);
  const uint32_t dw = 45, dh = 37, cw = 67, ch = 51;
  Rig rig = random_rig(rng, dw, dh, cw, ch);

  SECTION("no measurement anywhere: nothing lands") {
    const HostImage zero(dw, dh, PixelFormat::R16U, 0.0f);
    const HostImage gpu = run_gpu_depth_in_color(zero, rig);
    require_agrees(gpu, reference(zero, rig));
    CHECK(nonzero(gpu) == 0);
  }
  SECTION("points behind the colour camera are dropped, those in front kept") {
    // The colour camera 1.5 m in front of the depth camera: the top half at 1 m is behind it,
    // the bottom half at 2 m lands 0.5 m in front.
    rig.color_from_depth = Eigen::Translation3d(0, 0, -1.5) * Eigen::Isometry3d::Identity();
    HostImage depth(dw, dh, PixelFormat::R16U);
    for (uint32_t y = 0; y < dh; ++y)
      for (uint32_t x = 0; x < dw; ++x) depth.at(x, y) = y < dh / 2 ? 1000.0f : 2000.0f;
    const HostImage gpu = run_gpu_depth_in_color(depth, rig);
    require_agrees(gpu, reference(depth, rig));
    CHECK(nonzero(gpu) > 0);
    for (float mm : gpu.texels) CHECK((mm == 0.0f || std::abs(mm - 500.0f) <= 1.0f));
  }
  SECTION("points outside the colour image are dropped; partly outside, the rest lands") {
    const HostImage depth = scene(rng, dw, dh);
    rig.color_from_depth = Eigen::Translation3d(5.0, 0, 0) * Eigen::Isometry3d::Identity();
    const HostImage away = run_gpu_depth_in_color(depth, rig);
    require_agrees(away, reference(depth, rig));
    CHECK(nonzero(away) == 0);
    rig.color_from_depth = Eigen::Translation3d(1.2, -0.9, 0) * Eigen::Isometry3d::Identity();
    const HostImage partly = run_gpu_depth_in_color(depth, rig);
    require_agrees(partly, reference(depth, rig));
    CHECK(nonzero(partly) > 0);
    CHECK(nonzero(partly) < partly.texels.size() / 2);
  }
  SECTION("a depth edge: where both surfaces land, the nearest wins") {
    // Undistorted equal cameras 0.2 m apart along x: the near square (1 m) moves 12 pixels in
    // the colour image, the far wall (2 m) 6, so the square covers 6 columns of wall that the
    // colour camera cannot see, and uncovers 6 on its other side. Both ways round, so that the
    // covered wall is drawn before the square in one and after it in the other, whatever order
    // the device runs the cells in.
    for (const double baseline : {0.2, -0.2}) {
      INFO("colour camera at x = " << baseline << " m");
      Rig edge;
      edge.depth = {.width = 64, .height = 48, .fx = 60, .fy = 60, .cx = 31.5, .cy = 23.5, .distortion = {}};
      edge.color = edge.depth;
      edge.color_from_depth = Eigen::Translation3d(-baseline, 0, 0) * Eigen::Isometry3d::Identity();
      HostImage depth(64, 48, PixelFormat::R16U, 2000.0f), wall_only(64, 48, PixelFormat::R16U, 2000.0f);
      for (uint32_t y = 14; y <= 34; ++y)
        for (uint32_t x = 24; x <= 44; ++x) depth.at(x, y) = 1000.0f, wall_only.at(x, y) = 0.0f;
      const HostImage gpu = run_gpu_depth_in_color(depth, edge), ref = reference(depth, edge);
      require_agrees(gpu, ref);
      // The wall alone does land under the square: without the minimum it could win there.
      const HostImage wall = reference(wall_only, edge);
      const int shift = baseline > 0 ? -12 : 12;
      size_t contested = 0, near = 0;
      for (uint32_t y = 15; y <= 33; ++y)
        for (uint32_t x = uint32_t(24 + shift + 1); x <= uint32_t(44 + shift - 1); ++x) {
          if (std::abs(gpu.at(x, y) - 1000.0f) <= 1.0f) ++near;
          if (wall.at(x, y) != 0.0f) ++contested;
        }
      CHECK(near == 19 * 19);
      CHECK(contested >= 5 * 19);
    }
  }
  SECTION("identity with equal intrinsics gives the input back") {
    rig.color = rig.depth;
    rig.color_from_depth = Eigen::Isometry3d::Identity();
    HostImage depth(dw, dh, PixelFormat::R16U);
    for (uint32_t y = 0; y < dh; ++y)
      for (uint32_t x = 0; x < dw; ++x) depth.at(x, y) = float(1500 + 7 * x + 3 * y);
    const HostImage gpu = run_gpu_depth_in_color(depth, rig);
    require_agrees(gpu, reference(depth, rig));
    RT_REQUIRE_MATCHES(gpu, depth, 1.0, 0.0);
  }
}

TEST_CASE("depth_in_color refuses what it cannot register", "[depth_in_color][gpu]") {
  CameraIntrinsics empty;
  CHECK_THROWS_WITH(passes::depth_in_color_params(empty, Eigen::Isometry3d::Identity()), Catch::Contains("colour camera"));
  DepthInColorSettings negative;
  negative.max_jump_m = -1.0f;
  CHECK_THROWS_WITH(passes::DepthInColorPass(test::gpu(), negative), Catch::Contains("max_jump_m"));
}

// Not run by default (`remotetouch_gpu_tests "[.bench]"`): the pass's GPU time at the device's
// sizes, through pipeline::DepthRegistration as the commands use it, on a scene the depth
// camera measures everywhere (the worst case: a simulated person covers a few percent).
TEST_CASE("depth_in_color time at k4a sizes", "[.bench][depth_in_color]") {
  std::mt19937 rng(50);
  const std::pair<uint32_t, uint32_t> depth_modes[] = {{640, 576}, {512, 512}};
  const std::pair<uint32_t, uint32_t> color_modes[] = {{1280, 720}, {2560, 1440}};
  for (const auto& [dw, dh] : depth_modes)
    for (const auto& [cw, ch] : color_modes) {
      const Rig rig = random_rig(rng, dw, dh, cw, ch);
      const HostImage depth = scene(rng, dw, dh);
      pipeline::DepthRegistration registration(test::gpu(), rig.depth, rig.color, rig.color_from_depth);
      for (int frame = 0; frame < 10; ++frame) registration.run(depth);
      std::string passes;
      for (const vk::PassTiming& timing : registration.timings())
        passes += " " + timing.name + " " + std::to_string(timing.median_ms);
      WARN("depth " << dw << "x" << dh << " into colour " << cw << "x" << ch << ": " << registration.median_ms()
                    << " ms a capture (" << passes << " ) on " << test::gpu().device_name());
    }
}
