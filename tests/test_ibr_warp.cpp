// ibr_warp: GPU against the C++ reference. Colors to 2e-3 (sample positions through the float
// lens model differ by up to ~1e-3 pixel, random colors change by up to 1 per pixel), angles to
// 2e-3 rad (acos is steep near 0), other features to 1e-4; a sample exactly on a visibility or
// image border may go either way, so 1 pixel plus 0.5% of pixels may differ (stated tolerance).
// No NaN or Inf.
#include <limits>

#include "passes/ibr_blend.h"
#include "passes/ibr_foreground.h"
#include "passes/ibr_warp.h"
#include "sim/default_site.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr float kNaNIbrWarp = std::numeric_limits<float>::quiet_NaN();

passes::WarpedViews run_warp(const test::IbrRig& rig, const HostImage& fused, const HostImage& color,
                             const HostImage& points, const passes::WarpSettings& settings = {}) {
  const passes::IbrWarpPass pass(test::gpu(), settings);
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

// The camera-frame depth of target pixel (x, y)'s surface point at target depth `z` in view
// `view`, and where it projects in the view's depth and color images.
struct InView {
  Eigen::Vector3d q;
  passes::Float2 depth_pixel, color_pixel;
};
InView in_view(const test::IbrRig& rig, uint32_t view, uint32_t x, uint32_t y, double z) {
  const CameraIntrinsics& t = rig.target.intrinsics;
  const Eigen::Vector3d in_target((x - t.cx) / t.fx * z, (y - t.cy) / t.fy * z, z);
  const Eigen::Vector3d site = rig.target.camera_from_site.inverse() * in_target;
  const Eigen::Vector3d q = rig.cameras[view].depth.camera_from_site * site;
  const passes::Float3 qf{float(q.x()), float(q.y()), float(q.z())};
  const shader_abi::IbrCamera& camera = rig.table.cameras[view];
  return {q, passes::lens_project(camera.depth, qf), passes::lens_project(camera.color, qf)};
}

// Every view's own depth of the plane at target depth `plane_z` (where each depth texel's ray
// meets it; 0 where it meets it behind the camera or beyond 5 m), as a depth camera sees it.
HostImage points_seeing_plane(const test::IbrRig& rig, double plane_z) {
  const HostImage rays = passes::depth_ray_atlas(rig.cameras);
  HostImage points(rays.width, rays.height, PixelFormat::RGBA32F, 0.0f);
  const uint32_t band = rig.cameras[0].depth.intrinsics.height;
  for (uint32_t row = 0; row < rays.height; ++row)
    for (uint32_t x = 0; x < rays.width; ++x) {
      if (rays.at(x, row, 3) == 0.0f) continue;  // undistortion failed
      const Eigen::Vector3d position = rig.cameras[row / band].depth.camera_from_site.inverse().translation();
      const Eigen::Vector3d ray(rays.at(x, row, 0), rays.at(x, row, 1), rays.at(x, row, 2));  // site frame
      // The ray's point at camera depth d, position + d ray, has target depth origin + direction d.
      const double origin = (rig.target.camera_from_site * position).z();
      const double direction = (rig.target.camera_from_site.linear() * ray).z();
      const double d = (plane_z - origin) / direction;
      if (!(d > 0.0 && d < 5.0)) continue;
      const Eigen::Vector3d site = position + ray * d;
      float* texel = &points.texels[points.index(x, row)];
      texel[0] = float(site.x()), texel[1] = float(site.y()), texel[2] = float(site.z()), texel[3] = float(d);
    }
  return points;
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
    RT_REQUIRE_MOSTLY_MATCHES(gpu.warped, reference.warped, 2e-3, 1e-4, allowed);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.features, reference.features, 2e-3, 1e-4, allowed);
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
    const float bad[] = {kNaNIbrWarp, std::numeric_limits<float>::infinity(), -1.0f, 0.0f};
    for (size_t i = 0; i < fused.texels.size(); ++i) fused.texels[i] = bad[i % 4];
    const passes::WarpedViews gpu = run_warp(rig, fused, color, points);
    REQUIRE(visible(gpu.features) == 0);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.warped, HostImage(29, 38, PixelFormat::RGBA32F, 0.0f), 0.0, 1e-4, 0);
  }
  SECTION("surface points behind every camera are seen by none") {
    // The cameras turned to look straight ahead (+z, away from the eye): the surface 0.3 m from
    // the eye (z = -0.4, behind the glass) lies behind both. Through the sign of its depth a point
    // behind a camera projects where a point in front of it would; where that lands inside the
    // view's images and the depth test accepts anything (every own depth valid, 10 m tolerance),
    // only the test on the camera-frame depth rejects it.
    const test::IbrRig ahead = test::turned_away(rig);
    const HostImage fused(29, 19, PixelFormat::R32F, 0.3f);
    const HostImage valid_everywhere(41, 37 * 2, PixelFormat::RGBA32F, 0.7f);
    passes::WarpSettings accept_any;
    accept_any.visibility = {10.0f, 0.0f};
    size_t mirrored_inside = 0;
    for (uint32_t view = 0; view < 2; ++view)
      for (uint32_t y = 0; y < 19; ++y)
        for (uint32_t x = 0; x < 29; ++x) {
          const InView seen = in_view(ahead, view, x, y, 0.3);
          REQUIRE(seen.q.z() < 0.0);
          mirrored_inside += passes::inside_image(seen.depth_pixel, {41.0f, 37.0f}, 0.0f) &&
                             passes::inside_image(seen.color_pixel, {37.0f, 21.0f}, 0.0f);
        }
    REQUIRE(mirrored_inside > 100);
    const passes::WarpedViews gpu = run_warp(ahead, fused, color, valid_everywhere, accept_any);
    REQUIRE(visible(gpu.features) == 0);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.features,
                              passes::ibr_warp_reference(ahead.table, fused, color, valid_everywhere, accept_any).features,
                              0.0, 1e-4, 0);
  }
  SECTION("a view with no depth sees nothing (occlusion cannot be decided)") {
    // A tolerance of 10 m accepts any own depth against the surface, 0 included: only the test
    // that an own depth exists refuses these samples. The same surface with valid own depths
    // everywhere is seen, so the tolerance does let samples through.
    const HostImage fused = test::random_fused_depth(rng, 29, 19);
    passes::WarpSettings accept_any;
    accept_any.visibility = {10.0f, 0.0f};
    const HostImage valid_everywhere(points.width, points.height, PixelFormat::RGBA32F, 0.7f);
    REQUIRE(visible(passes::ibr_warp_reference(rig.table, fused, color, valid_everywhere, accept_any).features) > 100);
    HostImage no_depth = points;
    std::fill(no_depth.texels.begin(), no_depth.texels.end(), 0.0f);
    REQUIRE(visible(run_warp(rig, fused, color, no_depth, accept_any).features) == 0);
    REQUIRE(visible(passes::ibr_warp_reference(rig.table, fused, color, no_depth, accept_any).features) == 0);
  }
  SECTION("grazing angles stay finite") {
    // View 0 beside the surface (the plane 1.4 m from the eye, at z = 0.7), 0.25 m in front of
    // it, looking across it: its rays meet the eye's at 50 to 95 degrees. Both views' depths are
    // the plane as they see it, so that visibility passes where a sample lands near its texel.
    test::IbrRig grazing = rig;
    grazing.cameras[0].depth.camera_from_site = sim::camera_from_site_looking_at({-1.3, 0.1, 0.45}, {0.0, 0.1, 0.7});
    grazing.cameras[0].color.camera_from_site = grazing.cameras[0].depth.camera_from_site;
    grazing.table = passes::make_scene_table(grazing.target, grazing.cameras);
    const HostImage fused(29, 19, PixelFormat::R32F, 1.4f);
    const HostImage plane = points_seeing_plane(grazing, 1.4);
    const passes::WarpedViews gpu = run_warp(grazing, fused, color, plane);
    const passes::WarpedViews reference = passes::ibr_warp_reference(grazing.table, fused, color, plane);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.features, reference.features, 2e-3, 1e-4, 29 * 38 / 200);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.warped, reference.warped, 2e-3, 1e-4, 29 * 38 / 200);
    // The grazing view does sample the surface, mostly within 10 degrees of a right angle.
    size_t samples = 0, near_right_angle = 0;
    for (uint32_t y = 0; y < 19; ++y)
      for (uint32_t x = 0; x < 29; ++x)
        if (reference.features.at(x, y, 3) > 0.0f) {
          const double degrees = reference.features.at(x, y, 0) * 180.0 / M_PI;
          INFO(x << "," << y << ": " << degrees << " degrees");
          REQUIRE(degrees > 50.0);
          ++samples;
          near_right_angle += std::abs(degrees - 90.0) < 10.0;
        }
    INFO(samples << " samples of the grazing view, " << near_right_angle << " within 10 degrees of 90");
    REQUIRE(near_right_angle > 30);
  }
}

TEST_CASE("ibr_warp_reference counts how far its samples get", "[ibr_warp]") {
  std::mt19937 rng(33);
  SECTION("random inputs: each stage's count is the one before it, thinned") {
    const test::IbrRig rig = test::ibr_rig(3, 37, 21, 41, 37, 31, 23);
    const HostImage fused = test::random_fused_depth(rng, 31, 23);
    const HostImage color = test::random_image(rng, 37, 21 * 3, PixelFormat::RGBA8);
    HostImage points = points_agreeing_with(rng, rig);
    for (size_t i = 3; i < points.texels.size(); i += 4)
      if (points.texels[i] > 0.0f) points.texels[i] = std::uniform_real_distribution<float>(0.55f, 0.85f)(rng);
    passes::WarpWork work;
    const passes::WarpedViews reference =
        passes::ibr_warp_reference(rig.table, fused, color, points, passes::WarpSettings{}, &work);
    size_t surface = 0, covered = 0;
    for (uint32_t y = 0; y < 23; ++y)
      for (uint32_t x = 0; x < 31; ++x) {
        if (!(fused.at(x, y) > 0.0f)) continue;
        ++surface;
        bool seen = false;
        for (uint32_t view = 0; view < 3; ++view) seen = seen || reference.features.at(x, y + view * 23, 3) > 0.0f;
        covered += seen;
      }
    REQUIRE(work.surface_pixels == surface);
    REQUIRE(work.samples == 3 * surface);
    REQUIRE(work.seen == visible(reference.features));
    REQUIRE(work.covered == covered);
    REQUIRE(work.seen > 20);
    REQUIRE(work.samples >= work.in_front);
    REQUIRE(work.in_front >= work.inside);
    REQUIRE(work.inside > work.seen);
    REQUIRE(work.flops() > 200.0 * double(work.seen));
  }
  SECTION("no surface, or a surface behind every camera: only the stages before the test count") {
    const test::IbrRig rig = test::ibr_rig(2, 37, 21, 41, 37, 29, 19);
    const HostImage color = test::random_image(rng, 37, 42, PixelFormat::RGBA8);
    const HostImage points = points_agreeing_with(rng, rig);
    HostImage bad(29, 19, PixelFormat::R32F);
    const float values[] = {kNaNIbrWarp, std::numeric_limits<float>::infinity(), -1.0f, 0.0f};
    for (size_t i = 0; i < bad.texels.size(); ++i) bad.texels[i] = values[i % 4];
    passes::WarpWork work;
    (void)passes::ibr_warp_reference(rig.table, bad, color, points, passes::WarpSettings{}, &work);
    // An infinite depth is a surface (it is > 0) whose point is no number: in front of no camera.
    const uint64_t infinite = (29 * 19 + 2) / 4;
    REQUIRE(work.surface_pixels == infinite);
    REQUIRE(work.samples == 2 * infinite);
    REQUIRE(work.in_front == 0);
    REQUIRE(work.covered == 0);
    REQUIRE(work.flops() == (6 + 18) * double(infinite) + 18 * double(2 * infinite));

    const test::IbrRig ahead = test::turned_away(rig);
    (void)passes::ibr_warp_reference(ahead.table, HostImage(29, 19, PixelFormat::R32F, 0.3f), color, points,
                                     passes::WarpSettings{}, &work);
    REQUIRE(work.surface_pixels == 29 * 19);
    REQUIRE(work.in_front == 0);
    REQUIRE(work.flops() == (6 + 18) * 29.0 * 19 + 18 * 2.0 * 29 * 19);
  }
  SECTION("the lumigraph blend's count") {
    REQUIRE(passes::ulr_blend_flops(0, 0) == 0.0);
    REQUIRE(passes::ulr_blend_flops(3, 1) == 3 * 12.0 + 5.0);
  }
}
