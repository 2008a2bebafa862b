// ibr_warp and ibr_blend: GPU against the C++ references. Warping: colors to 2e-3 (sample
// positions through the float lens model differ by up to ~1e-3 pixel, random colors change by
// up to 1 per pixel), angles to 2e-3 rad (acos is steep near 0), other features to 1e-4; a
// sample exactly on a visibility or image border may go either way, so 1 pixel plus 0.5% of
// pixels may differ (stated tolerance). Blending from given atlases: 1e-5. No NaN or Inf.
#include <limits>

#include "passes/ibr_blend.h"
#include "passes/ibr_foreground.h"
#include "passes/ibr_warp.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"

using namespace rt;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

passes::WarpedViews run_warp(const test::IbrRig& rig, const HostImage& fused_in, const HostImage& color_in,
                             const HostImage& points_in) {
  vk::Context& context = test::gpu();
  const uint32_t tw = fused_in.width, th = fused_in.height, views = uint32_t(rig.cameras.size());
  vk::Image fused(context, {"fused depth", tw, th, PixelFormat::R32F});
  vk::Image color(context, {"color", color_in.width, color_in.height, PixelFormat::RGBA8});
  vk::Image points(context, {"points", points_in.width, points_in.height, PixelFormat::RGBA32F});
  vk::Image warped(context, {"warped", tw, th * views, PixelFormat::RGBA32F});
  vk::Image features(context, {"features", tw, th * views, PixelFormat::RGBA32F});
  vk::upload(context, fused, fused_in);
  vk::upload(context, color, color_in);
  vk::upload(context, points, points_in);
  passes::IbrSceneBuffer scene(context);
  scene.write(rig.table);
  const passes::IbrWarpPass pass(context);
  vk::FrameGraph graph(context, "test ibr_warp");
  pass.add_to(graph, scene, fused, color, points, warped, features, views);
  graph.run();
  return {vk::download(context, warped), vk::download(context, features)};
}

passes::Portrait run_blend(const HostImage& fused_in, const HostImage& warped_in, const HostImage& features_in,
                           uint32_t views, const passes::BlendSettings& settings = {}) {
  vk::Context& context = test::gpu();
  const uint32_t w = fused_in.width, h = fused_in.height;
  vk::Image fused(context, {"fused depth", w, h, PixelFormat::R32F});
  vk::Image warped(context, {"warped", w, h * views, PixelFormat::RGBA32F});
  vk::Image features(context, {"features", w, h * views, PixelFormat::RGBA32F});
  vk::Image portrait(context, {"portrait", w, h, PixelFormat::RGBA32F});
  vk::Image depth(context, {"portrait depth", w, h, PixelFormat::R32F});
  vk::upload(context, fused, fused_in);
  vk::upload(context, warped, warped_in);
  vk::upload(context, features, features_in);
  const passes::IbrBlendPass pass(context, settings);
  vk::FrameGraph graph(context, "test ibr_blend");
  pass.add_to(graph, fused, warped, features, portrait, depth, views);
  graph.run();
  return {vk::download(context, portrait), vk::download(context, depth)};
}

// A target-view depth of a surface about 1.3-1.5 m from the eye, with holes.
HostImage random_fused(std::mt19937& rng, uint32_t w, uint32_t h) {
  HostImage depth = test::random_image(rng, w, h, PixelFormat::R32F, 1.3f, 1.5f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (float& z : depth.texels)
    if (unit(rng) < 0.15f) z = 0.0f;
  return depth;
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
    const HostImage fused = random_fused(rng, width, height);
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
    REQUIRE(visible(run_warp(rig, random_fused(rng, 29, 19), color, no_depth).features) == 0);
  }
  SECTION("grazing angles stay finite") {
    test::IbrRig grazing = rig;
    // A camera beside the surface, looking across it: angles near 90 degrees.
    grazing.cameras[0].color.camera_from_site =
        Eigen::Isometry3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())) *
        Eigen::Translation3d(Eigen::Vector3d(1.5, -0.1, -0.6));
    grazing.cameras[0].depth.camera_from_site = grazing.cameras[0].color.camera_from_site;
    grazing.table = passes::make_scene_table(grazing.target, grazing.cameras);
    const HostImage fused = random_fused(rng, 29, 19);
    const passes::WarpedViews gpu = run_warp(grazing, fused, color, points);
    const passes::WarpedViews reference = passes::ibr_warp_reference(grazing.table, fused, color, points);
    require_close(gpu.features, reference.features, 2e-3, 29 * 38 / 200);
  }
}

TEST_CASE("ibr_blend on random atlases, odd sizes", "[ibr_blend][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(33);
  for (const auto& [width, height] : test::odd_sizes()) {
    for (uint32_t views : {1u, 2u, 4u, 6u}) {
      INFO(width << "x" << height << ", " << views << " views");
      const HostImage fused = random_fused(rng, width, height);
      const HostImage warped = test::random_image(rng, width, height * views, PixelFormat::RGBA32F);
      HostImage features = test::random_image(rng, width, height * views, PixelFormat::RGBA32F);
      std::uniform_real_distribution<float> unit(0.0f, 1.0f);
      for (size_t i = 0; i < features.texels.size(); i += 4) {
        features.texels[i] *= 1.5f;                                  // angle, radians
        features.texels[i + 3] = unit(rng) < 0.7f ? 1.0f : 0.0f;     // visible or not
      }
      for (int k : {2, 3}) {
        passes::BlendSettings settings;
        settings.best_views = k;
        const passes::Portrait gpu = run_blend(fused, warped, features, views, settings);
        const passes::Portrait reference = passes::ibr_blend_reference(fused, warped, features, views, settings);
        RT_REQUIRE_MATCHES(gpu.color, reference.color, 1e-5, 1e-5);
        RT_REQUIRE_MATCHES(gpu.depth, reference.depth, 0.0, 0.0);
      }
    }
  }
}

TEST_CASE("ibr_blend weights and hard cases", "[ibr_blend][gpu]") {
  test::NoValidationErrors no_errors;
  const uint32_t w = 3, h = 1;
  const HostImage fused(w, h, PixelFormat::R32F, 1.4f);
  auto views_with = [&](std::vector<std::array<float, 4>> color, std::vector<std::array<float, 4>> feature) {
    HostImage warped(w, h * uint32_t(color.size()), PixelFormat::RGBA32F), features = warped;
    for (uint32_t v = 0; v < color.size(); ++v)
      for (uint32_t x = 0; x < w; ++x)
        for (uint32_t c = 0; c < 4; ++c) warped.at(x, v, c) = color[v][c], features.at(x, v, c) = feature[v][c];
    return std::pair{warped, features};
  };

  SECTION("k = 3: the two best views blend by 1 - p / p_3, the third has weight 0") {
    const auto [warped, features] =
        views_with({{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}}, {{0.1f, 0, 1, 1}, {0.2f, 0, 1, 1}, {0.4f, 0, 1, 1}});
    const passes::Portrait gpu = run_blend(fused, warped, features, 3);
    // weights 1 - 0.1/0.4 = 0.75 and 1 - 0.2/0.4 = 0.5, normalised: 0.6 and 0.4.
    REQUIRE(gpu.color.at(0, 0, 0) == Approx(0.6f).epsilon(1e-5));
    REQUIRE(gpu.color.at(0, 0, 1) == Approx(0.4f).epsilon(1e-5));
    REQUIRE(gpu.color.at(0, 0, 2) == Approx(0.0f).margin(1e-6));
    REQUIRE(gpu.color.at(0, 0, 3) == 1.0f);
  }
  SECTION("a single visible view gives its color") {
    const auto [warped, features] = views_with({{0.2f, 0.3f, 0.4f, 1}, {1, 1, 1, 0}}, {{0.3f, 0, 1, 1}, {0, 0, 0, 0}});
    const passes::Portrait gpu = run_blend(fused, warped, features, 2);
    REQUIRE(gpu.color.at(1, 0, 0) == Approx(0.2f).epsilon(1e-5));
    REQUIRE(gpu.color.at(1, 0, 2) == Approx(0.4f).epsilon(1e-5));
    REQUIRE(gpu.color.at(1, 0, 3) == 1.0f);
  }
  SECTION("a surface point seen by no view: alpha 0 and color 0, not NaN") {
    const auto [warped, features] = views_with({{1, 1, 1, 0}, {1, 1, 1, 0}}, {{0, 0, 0, 0}, {0, 0, 0, 0}});
    const passes::Portrait gpu = run_blend(fused, warped, features, 2);
    RT_REQUIRE_MATCHES(gpu.color, HostImage(w, h, PixelFormat::RGBA32F, 0.0f), 0.0, 0.0);
    RT_REQUIRE_MATCHES(gpu.depth, HostImage(w, h, PixelFormat::R32F, 0.0f), 0.0, 0.0);
  }
  SECTION("equal penalties (all at the threshold) fall back to the best view") {
    const auto [warped, features] =
        views_with({{1, 0, 0, 1}, {0, 1, 0, 1}}, {{0.2f, 0, 1, 1}, {0.2f, 0, 1, 1}});
    passes::BlendSettings two;
    two.best_views = 2;
    const passes::Portrait gpu = run_blend(fused, warped, features, 2, two);
    RT_REQUIRE_MATCHES(gpu.color, passes::ibr_blend_reference(fused, warped, features, 2, two).color, 1e-6, 0.0);
    REQUIRE(gpu.color.at(0, 0, 3) == 1.0f);
  }
  SECTION("NaN features and colors count as not visible / clamped") {
    const auto [warped, features] =
        views_with({{kNaN, 0.5f, 2.0f, 1}, {0.1f, 0.1f, 0.1f, 1}}, {{kNaN, 0, 1, 1}, {0.3f, kNaN, 1, 1}});
    const passes::Portrait gpu = run_blend(fused, warped, features, 2);
    RT_REQUIRE_MATCHES(gpu.color, passes::ibr_blend_reference(fused, warped, features, 2).color, 1e-6, 0.0);
    REQUIRE(gpu.color.at(0, 0, 3) == 0.0f);
  }
}
