// ibr_carve (see-through carving): GPU against the C++ reference, and against the geometry of a
// gap: a view that sees a plane behind the fused surface carves it to that plane; a point within
// the probes' reach of that view's depth edge is left alone. The decision compares depths against a
// tolerance, so on random inputs a depth within float rounding of it may go either way: at most
// 1% of pixels, rounded down, may differ (stated tolerance; none in an image of fewer than 100
// pixels, so that no small image can be wrong); the rest match to 1e-5.
#include "passes/ibr_carve.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr uint32_t kDepthW = 9, kDepthH = 7;

HostImage run_gpu_ibr_carve(const test::IbrRig& rig, const HostImage& fused, const HostImage& points,
                  const passes::CarveSettings& settings = {}) {
  const passes::IbrCarvePass pass(test::gpu(), settings);
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_carve");
  pass.add_to(gpu.graph(), scene, gpu.input("fused depth", fused), gpu.input("points", points),
              gpu.output("carved depth", fused.width, fused.height, PixelFormat::R32F), uint32_t(rig.cameras.size()));
  return gpu.run().image("carved depth");
}

// View `view`'s texel (x, y) at camera depth `depth`: its site point (no lens distortion in
// these rigs) and the depth in w.
void set_texel(HostImage& points, const test::IbrRig& rig, uint32_t view, uint32_t x, uint32_t y, float depth) {
  const CameraIntrinsics& k = rig.cameras[view].depth.intrinsics;
  const Eigen::Vector3d in_camera((x - k.cx) / k.fx * depth, (y - k.cy) / k.fy * depth, depth);
  const Eigen::Vector3d site = rig.cameras[view].depth.camera_from_site.inverse() * in_camera;
  float* texel = &points.texels[points.index(x, y + view * kDepthH)];
  texel[0] = float(site.x()), texel[1] = float(site.y()), texel[2] = float(site.z()), texel[3] = depth;
}

// Pixel (x, y)'s target ray in view `view`'s camera frame: q(z) = origin + direction * z.
struct ViewRay {
  Eigen::Vector3d origin, direction;
  // The target depth where the ray reaches camera depth `depth` in the view.
  double target_depth_at(double depth) const { return (depth - origin.z()) / direction.z(); }
  Eigen::Vector3d at(double z) const { return origin + direction * z; }
};
ViewRay view_ray(const test::IbrRig& rig, uint32_t view, uint32_t x, uint32_t y) {
  const CameraIntrinsics& t = rig.target.intrinsics;
  const Eigen::Isometry3d camera_from_target =
      rig.cameras[view].depth.camera_from_site * rig.target.camera_from_site.inverse();
  const Eigen::Vector3d ray((x - t.cx) / t.fx, (y - t.cy) / t.fy, 1.0);
  return {camera_from_target.translation(), camera_from_target.linear() * ray};
}

}  // namespace

TEST_CASE("ibr_carve on random inputs, odd sizes", "[ibr_carve][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(51);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  size_t carved_pixels = 0;
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const test::IbrRig rig = test::ibr_rig(3, 37, 21, kDepthW, kDepthH, width, height, false);
    HostImage fused = test::random_image(rng, width, height, PixelFormat::R32F, 1.0f, 1.4f);
    for (size_t i = 0; i < fused.texels.size(); i += 7) fused.texels[i] = 0.0f;
    // Each view sees surfaces 0.3-1.5 m away, a fifth of its texels invalid.
    HostImage points(kDepthW, kDepthH * 3, PixelFormat::RGBA32F, 0.0f);
    for (uint32_t view = 0; view < 3; ++view)
      for (uint32_t y = 0; y < kDepthH; ++y)
        for (uint32_t x = 0; x < kDepthW; ++x)
          if (unit(rng) >= 0.2f) set_texel(points, rig, view, x, y, 0.3f + 1.2f * unit(rng));
    const HostImage gpu = run_gpu_ibr_carve(rig, fused, points);
    const HostImage reference = passes::ibr_carve_reference(rig.table, fused, points);
    const auto comparison = test::compare_pixels(gpu, reference, 1e-5, 1e-5);
    REQUIRE(comparison.non_finite == 0);
    INFO(comparison.mismatched_pixels << " pixels differ, max " << comparison.max_abs_error);
    REQUIRE(comparison.mismatched_pixels <= size_t(width) * height / 100);
    for (size_t i = 0; i < fused.texels.size(); ++i) {
      if (fused.texels[i] == 0.0f) REQUIRE(gpu.texels[i] == 0.0f);  // nothing stays nothing
      REQUIRE(gpu.texels[i] >= fused.texels[i]);                      // carving only moves surfaces back
      carved_pixels += gpu.texels[i] > fused.texels[i];
    }
  }
  REQUIRE(carved_pixels > 0);
}

TEST_CASE("ibr_carve: a view that sees through the fused surface carves it to what it sees", "[ibr_carve][gpu]") {
  test::NoValidationErrors no_errors;
  const uint32_t w = 23, h = 15;
  const test::IbrRig rig = test::ibr_rig(2, 37, 21, kDepthW, kDepthH, w, h, false);
  // A "finger" at target depth 1.0 m everywhere. View 0 looks through it at a plane 1.8 m from
  // it; view 1's depth is nearer still (an occluder: it neither sees through nor sees the plane).
  const float finger_m = 1.0f, plane_m = 1.8f;
  const HostImage fused(w, h, PixelFormat::R32F, finger_m);
  HostImage points(kDepthW, kDepthH * 2, PixelFormat::RGBA32F, 0.0f);
  // View 0 sees the plane on texel columns up to `edge_column`, an occluder beyond.
  const uint32_t edge_column = 5;
  for (uint32_t y = 0; y < kDepthH; ++y)
    for (uint32_t x = 0; x < kDepthW; ++x) {
      set_texel(points, rig, 0, x, y, x < edge_column ? plane_m : 0.1f);
      set_texel(points, rig, 1, x, y, 0.1f);
    }
  const HostImage gpu = run_gpu_ibr_carve(rig, fused, points);
  const HostImage reference = passes::ibr_carve_reference(rig.table, fused, points);
  RT_REQUIRE_MATCHES(gpu, reference, 1e-5, 1e-5);
  size_t carved = 0, kept_beyond_edge = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      INFO(x << "," << y);
      const ViewRay ray = view_ray(rig, 0, x, y);
      const Eigen::Vector3d finger = ray.at(finger_m);
      const auto pixel = passes::lens_project(rig.table.cameras[0].depth,
                                              {float(finger.x()), float(finger.y()), float(finger.z())});
      // Where the probes around the finger's projection all fall on the plane's
      // texels (clear of the edge at column edge_column - 0.5; probes past the border clamp), view 0
      // sees through, and the plane point behind is in both of its images: carved to the plane.
      const double behind = ray.target_depth_at(plane_m);
      const Eigen::Vector3d plane_point = ray.at(behind);
      const auto plane_pixel = passes::lens_project(rig.table.cameras[0].depth, {float(plane_point.x()),
                                                                                 float(plane_point.y()), plane_m});
      const auto plane_color = passes::lens_project(rig.table.cameras[0].color, {float(plane_point.x()),
                                                                                   float(plane_point.y()), plane_m});
      const float probe = passes::CarveSettings{}.probe_texels;
      const bool clear_of_edge = pixel.x + probe < float(edge_column) - 0.5f - 1e-3f;
      REQUIRE(finger.z() + 0.03 + 0.01 * plane_m < plane_m - 1e-3);  // the plane is behind the finger
      const bool in_images = passes::inside_image(pixel, {float(kDepthW), float(kDepthH)}, 0.0f) &&
                             passes::inside_image(plane_pixel, {float(kDepthW), float(kDepthH)}, 0.0f) &&
                             passes::inside_image(plane_color, {37.0f, 21.0f}, 0.0f) &&
                             std::floor(plane_pixel.x + 0.5f) < float(edge_column);
      if (clear_of_edge && in_images) {
        REQUIRE(gpu.at(x, y) == Approx(behind).margin(1e-4));
        ++carved;
      } else if (pixel.x - probe > float(edge_column) - 0.5f + 1e-3f || !in_images) {
        REQUIRE(gpu.at(x, y) == finger_m);  // a probe on the occluder's side, or nothing seen behind
        kept_beyond_edge += passes::inside_image(pixel, {float(kDepthW), float(kDepthH)}, 0.0f) &&
                            pixel.x - probe > float(edge_column) - 0.5f;
      }
    }
  REQUIRE(carved > 0);
  REQUIRE(kept_beyond_edge > 0);  // the edge crosses the view: both sides are tested
}

TEST_CASE("ibr_carve hard cases", "[ibr_carve][gpu]") {
  test::NoValidationErrors no_errors;
  const uint32_t w = 13, h = 11;
  const test::IbrRig rig = test::ibr_rig(2, 37, 21, kDepthW, kDepthH, w, h, false);
  HostImage far_planes(kDepthW, kDepthH * 2, PixelFormat::RGBA32F, 0.0f);
  for (uint32_t view = 0; view < 2; ++view)
    for (uint32_t y = 0; y < kDepthH; ++y)
      for (uint32_t x = 0; x < kDepthW; ++x) set_texel(far_planes, rig, view, x, y, 1.2f);
  SECTION("no depth, NaN, infinite and negative depths give no depth; no NaN anywhere") {
    HostImage fused(w, h, PixelFormat::R32F, 0.0f);
    fused.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
    fused.at(2, 2) = -1.0f;
    fused.at(3, 3) = std::numeric_limits<float>::infinity();
    const HostImage gpu = run_gpu_ibr_carve(rig, fused, far_planes);
    REQUIRE(test::count_non_finite(gpu) == 0);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        REQUIRE(gpu.at(x, y) == 0.0f);
    RT_REQUIRE_MATCHES(gpu, passes::ibr_carve_reference(rig.table, fused, far_planes), 0.0, 0.0);
  }
  SECTION("views without depth (0 everywhere) carve nothing") {
    const HostImage fused(w, h, PixelFormat::R32F, 1.1f);
    const HostImage empty(kDepthW, kDepthH * 2, PixelFormat::RGBA32F, 0.0f);
    RT_REQUIRE_MATCHES(run_gpu_ibr_carve(rig, fused, empty), fused, 0.0, 0.0);
  }
  SECTION("points next to the eye, behind the top camera and outside the other's image, stay") {
    const HostImage fused(w, h, PixelFormat::R32F, 0.05f);
    size_t behind_a_camera = 0;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        for (uint32_t view = 0; view < 2; ++view) {
          const Eigen::Vector3d q = view_ray(rig, view, x, y).at(0.05);
          const auto pixel = passes::lens_project(rig.table.cameras[view].depth, {float(q.x()), float(q.y()), float(q.z())});
          const bool behind = q.z() <= 1e-4;
          REQUIRE((behind || !passes::inside_image(pixel, {float(kDepthW), float(kDepthH)}, 0.0f)));
          behind_a_camera += behind;
        }
    REQUIRE(behind_a_camera > 0);
    RT_REQUIRE_MATCHES(run_gpu_ibr_carve(rig, fused, far_planes), fused, 0.0, 0.0);
    RT_REQUIRE_MATCHES(passes::ibr_carve_reference(rig.table, fused, far_planes), fused, 0.0, 0.0);
  }
  SECTION("a surface behind that no view sees is not taken: carving never uncovers a pixel") {
    // The views see through, but their points lie far off every ray (xyz inconsistent with w) and
    // without marching the surface behind is where no view's depth agrees.
    HostImage misplaced = far_planes;
    for (size_t i = 0; i < misplaced.texels.size(); i += 4) misplaced.texels[i + 2] += 3.0f;
    passes::CarveSettings no_march;
    no_march.march_steps = 0;
    const HostImage fused(w, h, PixelFormat::R32F, 1.1f);
    const HostImage gpu = run_gpu_ibr_carve(rig, fused, misplaced, no_march);
    RT_REQUIRE_MATCHES(gpu, fused, 0.0, 0.0);
    RT_REQUIRE_MATCHES(passes::ibr_carve_reference(rig.table, fused, misplaced, no_march), fused, 0.0, 0.0);
    REQUIRE(run_gpu_ibr_carve(rig, fused, far_planes, no_march).texels != fused.texels);  // consistent points do carve
  }
  SECTION("bad settings are refused") {
    passes::CarveSettings bad;
    bad.probe_texels = 0.5f;
    REQUIRE_THROWS_WITH(passes::IbrCarvePass(test::gpu(), bad), Catch::Contains("probe_texels"));
    REQUIRE_THROWS_WITH(passes::IbrCarvePass(test::gpu(), {}, {0.03f, -0.01f}), Catch::Contains("visibility"));
    HostImage odd_points(kDepthW, 15, PixelFormat::RGBA32F, 0.0f);  // not two bands
    REQUIRE_THROWS_WITH(run_gpu_ibr_carve(rig, HostImage(w, h, PixelFormat::R32F, 1.1f), odd_points), Catch::Contains("bands"));
  }
}
