// ibr_foreground pass: GPU against the C++ reference. Tolerance: 1e-5 m absolute + 1e-5
// relative on positions and depths (float matrix products in a different order); the
// foreground decision itself must agree on every pixel.
#include <limits>

#include "passes/ibr_foreground.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

HostImage run_gpu_ibr_foreground(const test::IbrRig& rig, const HostImage& depth_mm, const HostImage& rays,
                  const passes::ForegroundSettings& settings = {}) {
  const passes::IbrForegroundPass pass(test::gpu(), settings);
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_foreground");
  const uint32_t views = uint32_t(rig.cameras.size());
  passes::IbrTiles tiles(test::gpu(), "point tiles", depth_mm.width, depth_mm.height / views, views);
  pass.add_to(gpu.graph(), scene, gpu.input("depth mm", depth_mm), gpu.input("depth rays", rays),
              gpu.output("points", depth_mm.width, depth_mm.height, PixelFormat::RGBA32F), tiles, views);
  const HostImage points = gpu.run(2).image("points");  // a second frame lists each tile once again
  // The tiles listed for the splat are those holding a point, each once.
  REQUIRE(test::listed_tiles(tiles) == passes::ibr_tiles_reference(points, views, 3));
  return points;
}

size_t foreground_pixels(const HostImage& points) {
  size_t count = 0;
  for (size_t i = 3; i < points.texels.size(); i += 4) count += points.texels[i] > 0.0f;
  return count;
}

void require_match(const HostImage& gpu, const HostImage& reference) {
  const auto comparison = test::compare_pixels(gpu, reference, 1e-5, 1e-5);
  INFO("max abs error " << comparison.max_abs_error);
  REQUIRE(comparison.non_finite == 0);
  REQUIRE(comparison.mismatched_pixels == 0);
}

}  // namespace

TEST_CASE("ibr_foreground on random depths of odd sizes", "[ibr_foreground][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(11);
  for (const auto& [width, height] : test::odd_sizes()) {
    for (uint32_t views : {1u, 3u}) {
      INFO(width << "x" << height << ", " << views << " views");
      const test::IbrRig rig = test::ibr_rig(views, 16, 9, width, height, 8, 5);
      const HostImage depth = test::random_depth_atlas(rng, rig);
      const HostImage rays = passes::depth_ray_atlas(rig.cameras);
      const HostImage reference = passes::ibr_foreground_reference(rig.table, depth, rays);
      require_match(run_gpu_ibr_foreground(rig, depth, rays), reference);
      if (width * height > 1000) REQUIRE(foreground_pixels(reference) > width * height / 4);  // not a vacuous test
    }
  }
}

TEST_CASE("ibr_foreground hard cases", "[ibr_foreground][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(12);
  const test::IbrRig rig = test::ibr_rig(2, 16, 9, 23, 17, 8, 5);
  const HostImage rays = passes::depth_ray_atlas(rig.cameras);

  SECTION("depth 0 everywhere gives no foreground") {
    const HostImage depth(23, 34, PixelFormat::R16U, 0.0f);
    const HostImage gpu = run_gpu_ibr_foreground(rig, depth, rays);
    REQUIRE(foreground_pixels(gpu) == 0);
    require_match(gpu, passes::ibr_foreground_reference(rig.table, depth, rays));
  }
  SECTION("one view with no depth, the other intact") {
    HostImage depth = test::random_depth_atlas(rng, rig, 0.0f);
    std::fill(depth.texels.begin(), depth.texels.begin() + 23 * 17, 0.0f);
    const HostImage gpu = run_gpu_ibr_foreground(rig, depth, rays);
    require_match(gpu, passes::ibr_foreground_reference(rig.table, depth, rays));
    REQUIRE(foreground_pixels(passes::band_of(gpu, 0, 17)) == 0);
    REQUIRE(foreground_pixels(passes::band_of(gpu, 1, 17)) > 100);
  }
  SECTION("everything beyond the user's volume is background") {
    const HostImage depth(23, 34, PixelFormat::R16U, 3000.0f);  // 3 m: the wall behind the user
    REQUIRE(foreground_pixels(run_gpu_ibr_foreground(rig, depth, rays)) == 0);
  }
  SECTION("an isolated pixel (a flying pixel) is removed; a plane's edge row survives") {
    HostImage depth(23, 34, PixelFormat::R16U, 0.0f);
    depth.at(5, 5) = 700.0f;  // alone
    for (uint32_t y = 20; y < 34; ++y)
      for (uint32_t x = 0; x < 23; ++x) depth.at(x, y) = 700.0f;  // all of view 1
    const HostImage gpu = run_gpu_ibr_foreground(rig, depth, rays);
    require_match(gpu, passes::ibr_foreground_reference(rig.table, depth, rays));
    REQUIRE(gpu.at(5, 5, 3) == 0.0f);
    REQUIRE(gpu.at(11, 20, 3) > 0.0f);  // top row of view 1's plane: 5 agreeing neighbours
    REQUIRE(gpu.at(0, 20, 3) == 0.0f);  // the plane's corner has 3: removed
  }
  SECTION("rays where undistortion failed are invalid") {
    HostImage broken = rays;
    for (size_t i = 0; i < broken.texels.size(); i += 4) broken.texels[i + 3] = 0.0f;
    REQUIRE(foreground_pixels(run_gpu_ibr_foreground(rig, test::random_depth_atlas(rng, rig), broken)) == 0);
  }
  SECTION("bad settings are refused with a message") {
    passes::ForegroundSettings bad;
    bad.volume_min.x() = std::numeric_limits<float>::quiet_NaN();
    REQUIRE_THROWS_WITH(passes::IbrForegroundPass(test::gpu(), bad), Catch::Contains("volume"));
  }
}
