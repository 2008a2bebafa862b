// ibr_warp: GPU against the C++ reference. Colors to 2e-3 (sample positions through the float
// lens model differ by up to ~1e-3 pixel, random colors change by up to 1 per pixel), angles to
// 2e-3 rad (acos is steep near 0), other features to 1e-4; a sample exactly on a visibility or
// image border may go either way, so 1 pixel plus 0.5% of pixels may differ (stated tolerance).
// No NaN or Inf.
#include <limits>

#include "passes/ibr_foreground.h"
#include "passes/ibr_warp.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

passes::WarpedViews run_warp(const test::IbrRig& rig, const HostImage& fused, const HostImage& color,
                             const HostImage& points) {
  const passes::IbrWarpPass pass(test::gpu());
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_warp");
  const uint32_t tw = fused.width, th = fused.height, views = uint32_t(rig.cameras.size());
  pass.add_to(gpu.graph(), scene, gpu.input("fused depth", fused), gpu.input("color", color), gpu.input("points", points),
              gpu.output("warped", tw, th * views, PixelFormat::RGBA32F),
              gpu.output("features", tw, th * views, PixelFormat::RGBA32F), views);
  const test::PassOutputs out = gpu.run();
  return {out.image("warped"), out.image("features")};
}

// Points whose own depth agrees with the fused surface often enough to exercise both outcomes.
HostImage points_agreeing_with(std::mt19937& rng, const test::IbrRig& rig) {
  return passes::ibr_foreground_reference(rig.table, test::random_depth_atlas(rng, rig, 0.05f),
                                          passes::depth_ray_atlas(rig.cameras));
}

void require_close(const HostImage& gpu, const HostImage& reference, double abs_tol, size_t allowed) {
  const auto comparison = test::compare_pixels(gpu, reference, abs_tol, 1e-4);
  INFO(comparison.mismatched_pixels << " of " << gpu.width * gpu.height << " pixels differ, max "
                                    << comparison.max_abs_error);
  REQUIRE(comparison.non_finite == 0);
  REQUIRE(comparison.mismatched_pixels <= allowed);
}

size_t visible(const HostImage& features) {
  size_t count = 0;
  for (size_t i = 3; i < features.texels.size(); i += 4) count += features.texels[i] > 0.0f;
  return count;
}

}  // namespace

TEST_CASE("ibr_warp on random inputs, odd target sizes", "[ibr_warp][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(31);
  size_t total_visible = 0;
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const test::IbrRig rig = test::ibr_rig(3, 37, 21, 41, 37, width, height);
    const HostImage fused = test::random_fused_depth(rng, width, height);
    const HostImage color = test::random_image(rng, 37, 21 * 3, PixelFormat::RGBA8);
    HostImage points = points_agreeing_with(rng, rig);
    // Make each view's own depth agree with the fused surface where it has one: visibility passes.
    for (size_t i = 3; i < points.texels.size(); i += 4)
      if (points.texels[i] > 0.0f) points.texels[i] = std::uniform_real_distribution<float>(0.55f, 0.85f)(rng);
    const passes::WarpedViews gpu = run_warp(rig, fused, color, points);
    const passes::WarpedViews reference = passes::ibr_warp_reference(rig.table, fused, color, points);
    const size_t allowed = 1 + size_t(width) * height * 3 / 200;
    require_close(gpu.warped, reference.warped, 2e-3, allowed);
    require_close(gpu.features, reference.features, 2e-3, allowed);
    total_visible += visible(reference.features);
  }
  REQUIRE(total_visible > 1000);  // some samples pass the visibility test
}

TEST_CASE("ibr_warp hard cases", "[ibr_warp][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(32);
  const test::IbrRig rig = test::ibr_rig(2, 37, 21, 41, 37, 29, 19);
  const HostImage color = test::random_image(rng, 37, 42, PixelFormat::RGBA8);
  const HostImage points = points_agreeing_with(rng, rig);

  SECTION("NaN, Inf, negative and zero fused depths give no sample") {
    HostImage fused(29, 19, PixelFormat::R32F);
    const float bad[] = {kNaN, std::numeric_limits<float>::infinity(), -1.0f, 0.0f};
    for (size_t i = 0; i < fused.texels.size(); ++i) fused.texels[i] = bad[i % 4];
    const passes::WarpedViews gpu = run_warp(rig, fused, color, points);
    REQUIRE(visible(gpu.features) == 0);
    require_close(gpu.warped, HostImage(29, 38, PixelFormat::RGBA32F, 0.0f), 0.0, 0);
  }
  SECTION("surface points behind every camera are seen by none") {
    const HostImage fused(29, 19, PixelFormat::R32F, 0.3f);  // 0.3 m from the eye: z = -0.4, behind the glass
    const passes::WarpedViews gpu = run_warp(rig, fused, color, points);
    REQUIRE(visible(gpu.features) == 0);
    require_close(gpu.features, passes::ibr_warp_reference(rig.table, fused, color, points).features, 0.0, 0);
  }
  SECTION("a view with no depth sees nothing (occlusion cannot be decided)") {
    HostImage no_depth = points;
    std::fill(no_depth.texels.begin(), no_depth.texels.end(), 0.0f);
    REQUIRE(visible(run_warp(rig, test::random_fused_depth(rng, 29, 19), color, no_depth).features) == 0);
  }
  SECTION("grazing angles stay finite") {
    test::IbrRig grazing = rig;
    // A camera beside the surface, looking across it: angles near 90 degrees.
    grazing.cameras[0].color.camera_from_site =
        Eigen::Isometry3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())) *
        Eigen::Translation3d(Eigen::Vector3d(1.5, -0.1, -0.6));
    grazing.cameras[0].depth.camera_from_site = grazing.cameras[0].color.camera_from_site;
    grazing.table = passes::make_scene_table(grazing.target, grazing.cameras);
    const HostImage fused = test::random_fused_depth(rng, 29, 19);
    const passes::WarpedViews gpu = run_warp(grazing, fused, color, points);
    const passes::WarpedViews reference = passes::ibr_warp_reference(grazing.table, fused, color, points);
    require_close(gpu.features, reference.features, 2e-3, 29 * 38 / 200);
  }
}
