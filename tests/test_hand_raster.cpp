// hand_raster pass: the GPU against the C++ reference on the skinned template seen from target
// views of odd sizes, unlit and shaded by a light estimate, and on the hard cases (a hand across
// the near plane, a hand behind the eye, no triangles, collapsed normals, a shade far outside
// its clamp). Tolerances away from triangle edges: mask exact, linear depth 1e-5 relative, unit
// normal 1e-4, color 4e-3 absolute times the shade (the GPU's 8-bit sub-texel filter weights on
// a texture whose nails and creases step by up to 0.2); within one pixel of an edge the GPU's
// tie-breaking may differ.
#include <cmath>
#include <random>

#include "geometry/target_view.h"
#include "hand/hand_bones.h"
#include "hand/hand_template.h"
#include "hand/shading_fit.h"
#include "passes/hand_raster.h"
#include "passes/hand_skinning.h"
#include "sim/hand_model.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::SkinnedVertex;

namespace {

struct GpuRaster {
  HostImage color, depth_m, mask, normal;
};

// A light from above and in front, as hand/shading_fit.h's coefficients.
hand::ShadingVector test_light() {
  hand::ShadingVector c = hand::ShadingVector::Zero();
  c << 0.8, 0.1, 0.35, -0.25, 0.05, -0.1, 0.08, 0.12, -0.06;
  return c;
}

passes::HandRasterParams params_of(const Camera& camera, const hand::ShadingVector& shading) {
  return passes::hand_raster_params(passes::raster_view(camera, 0.05, 10.0), hand::raster_shading(shading));
}

GpuRaster run_gpu_hand_raster(const std::vector<SkinnedVertex>& skinned, const std::vector<uint32_t>& indices, const HostImage& texture,
                  const Camera& camera, const hand::ShadingVector& shading = hand::unlit_shading()) {
  const passes::HandRasterPass pass(test::gpu());
  const vk::Sampler sampler(test::gpu(), "bilinear clamp");
  test::PassHarness gpu("hand_raster");
  const uint32_t w = camera.intrinsics.width, h = camera.intrinsics.height;
  const auto params = params_of(camera, shading);
  pass.add_to(gpu.graph(), gpu.input_buffer("skinned", skinned), gpu.input_buffer("indices", indices),
              [n = uint32_t(indices.size())] { return n; }, gpu.input("skin texture", texture), sampler,
              [params] { return params; },
              {&gpu.output("hand color", w, h, PixelFormat::RGBA32F), &gpu.output("hand depth", w, h, PixelFormat::R32F),
               &gpu.output("hand mask", w, h, PixelFormat::R32F), &gpu.output("hand normal", w, h, PixelFormat::RGBA32F),
               &gpu.scratch("hand depth buffer", w, h, PixelFormat::D32F)});
  const test::PassOutputs out = gpu.run();
  return {out.image("hand color"), out.image("hand depth"), out.image("hand mask"), out.image("hand normal")};
}

size_t require_matches_hand_raster(const GpuRaster& gpu, const passes::HandRasterReference& reference, double color_tolerance = 4e-3) {
  REQUIRE(test::count_non_finite(gpu.color) == 0);
  REQUIRE(test::count_non_finite(gpu.depth_m) == 0);
  REQUIRE(test::count_non_finite(gpu.mask) == 0);
  REQUIRE(test::count_non_finite(gpu.normal) == 0);
  size_t covered = 0;
  size_t gpu_total = 0, ref_total = 0;
  for (size_t i = 0; i < gpu.mask.texels.size(); ++i) gpu_total += gpu.mask.texels[i] > 0, ref_total += reference.mask.texels[i] > 0;
  INFO("hand pixels: GPU " << gpu_total << ", reference " << ref_total);
  for (uint32_t y = 0; y < gpu.mask.height; ++y)
    for (uint32_t x = 0; x < gpu.mask.width; ++x) {
      const float m = gpu.mask.at(x, y);
      REQUIRE((m == 0.0f || m == 1.0f));
      if (reference.near_edge.at(x, y) != 0.0f) continue;
      INFO("pixel " << x << ", " << y);
      REQUIRE(m == reference.mask.at(x, y));
      if (m == 0.0f) {
        REQUIRE(gpu.depth_m.at(x, y) == 0.0f);
        REQUIRE(gpu.color.at(x, y, 3) == 0.0f);
        REQUIRE(gpu.normal.at(x, y, 3) == 0.0f);
        continue;
      }
      ++covered;
      REQUIRE(std::abs(gpu.depth_m.at(x, y) - reference.depth_m.at(x, y)) <= 1e-5 * reference.depth_m.at(x, y));
      for (uint32_t c = 0; c < 4; ++c) {
        REQUIRE(std::abs(gpu.color.at(x, y, c) - reference.color.at(x, y, c)) <= color_tolerance);
        REQUIRE(std::abs(gpu.normal.at(x, y, c) - reference.normal.at(x, y, c)) <= 1e-4);
      }
    }
  if (gpu_total > 200) CHECK(covered > gpu_total / 4);
  return covered;
}

// The skinned template for a hand placed in the site frame.
std::vector<SkinnedVertex> skinned_hand(const hand::HandTemplate& hand, const Eigen::Vector3d& palm, double curl) {
  sim::HandPlacement placement;
  placement.palm = palm;
  placement.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1, 0.3).normalized()));
  placement.curl = curl;
  HandSkeleton skeleton = sim::build_hand(placement, hand.is_left, 1.0);
  skeleton.elbow = skeleton.wrist - 0.25 * skeleton.direction;
  const hand::BonePose pose = hand::pose_bones(skeleton, hand.rest);
  REQUIRE(pose.ok());
  return passes::hand_skinning_reference(hand.vertices, hand::skinning_matrices(pose.frames, hand.rest));
}

// The remote viewer's eye 0.7 m behind the screen, looking at the hand.
Camera view_of(uint32_t width, uint32_t height) {
  return target_view_camera(Eigen::Vector3d(0.02, 0.05, -0.7), Screen{}, width, height);
}

// A close pinhole view of the hand (the pass takes any pinhole), so that it fills the image.
Camera close_view(uint32_t width, uint32_t height) {
  Camera camera = view_of(width, height);
  camera.intrinsics.fx = camera.intrinsics.fy = 1.1 * width;
  camera.intrinsics.cx = 0.5 * width - 0.5 + 0.3;
  camera.intrinsics.cy = 0.5 * height - 0.5 - 0.2;
  camera.camera_from_site.translation() = -(camera.camera_from_site.linear() * Eigen::Vector3d(0.0, 0.05, -0.15));
  return camera;
}

}  // namespace

TEST_CASE("hand_raster matches the reference on the skinned template at odd sizes") {
  test::NoValidationErrors no_errors;
  const hand::HandTemplate hand = hand::build_hand_template(false);
  for (auto [w, h] : std::vector<std::pair<uint32_t, uint32_t>>{{97, 55}, {160, 90}, {1, 1}, {33, 1}}) {
    INFO(w << "x" << h);
    // The hand fills a good part of a small view: 20 cm in front of the screen.
    const auto skinned = skinned_hand(hand, Eigen::Vector3d(0.0, 0.05, 0.2), 0.3);
    const Camera camera = close_view(w, h);
    const size_t covered = require_matches_hand_raster(
        run_gpu_hand_raster(skinned, hand.indices, hand.texture, camera),
        passes::hand_raster_reference(skinned, hand.indices, hand.texture, params_of(camera, hand::unlit_shading()), w, h));
    if (w * h > 1000) CHECK(covered > w * h / 50);
  }
}

TEST_CASE("hand_raster shades by the light estimate as the reference does, and clamps it") {
  test::NoValidationErrors no_errors;
  const hand::HandTemplate hand = hand::build_hand_template(false);
  const auto skinned = skinned_hand(hand, Eigen::Vector3d(0.0, 0.05, 0.2), 0.3);
  const Camera camera = close_view(83, 61);
  hand::ShadingVector harsh = test_light();
  harsh *= 6.0;  // mostly outside [RT_HAND_SHADE_MIN, RT_HAND_SHADE_MAX]
  for (const hand::ShadingVector& shading : {test_light(), harsh}) {
    const GpuRaster lit = run_gpu_hand_raster(skinned, hand.indices, hand.texture, camera, shading);
    require_matches_hand_raster(lit, passes::hand_raster_reference(skinned, hand.indices, hand.texture, params_of(camera, shading), 83, 61),
                    4e-3 * RT_HAND_SHADE_MAX);
    // The shade does change the picture: otherwise the test above could pass on an unlit raster.
    const GpuRaster unlit = run_gpu_hand_raster(skinned, hand.indices, hand.texture, camera);
    double difference = 0;
    for (size_t i = 0; i < lit.color.texels.size(); ++i) difference += std::abs(lit.color.texels[i] - unlit.color.texels[i]);
    CHECK(difference > 1.0);
  }
  // Collapsed normals: drawn unlit, with no normal, never NaN.
  std::vector<SkinnedVertex> flat = skinned;
  for (SkinnedVertex& v : flat) v.normal_v[0] = v.normal_v[1] = v.normal_v[2] = 0.0f;
  const GpuRaster collapsed = run_gpu_hand_raster(flat, hand.indices, hand.texture, camera, test_light());
  require_matches_hand_raster(collapsed, passes::hand_raster_reference(flat, hand.indices, hand.texture, params_of(camera, test_light()), 83, 61));
  for (uint32_t y = 0; y < 61; ++y)
    for (uint32_t x = 0; x < 83; ++x) REQUIRE(collapsed.normal.at(x, y, 3) == 0.0f);
}

TEST_CASE("hand_raster hard cases: across the near plane, behind the eye, nothing to draw") {
  test::NoValidationErrors no_errors;
  const hand::HandTemplate hand = hand::build_hand_template(true);
  const Camera camera = view_of(61, 47);
  const auto view = params_of(camera, hand::unlit_shading());
  const Eigen::Vector3d eye = camera.position_in_site();
  for (const Eigen::Vector3d& palm : {Eigen::Vector3d(eye + Eigen::Vector3d(0, 0, 0.1)),   // straddles the near plane
                                      Eigen::Vector3d(eye - Eigen::Vector3d(0, 0, 0.4))}) {  // behind the eye
    const auto skinned = skinned_hand(hand, palm, 0.5);
    require_matches_hand_raster(run_gpu_hand_raster(skinned, hand.indices, hand.texture, camera),
                    passes::hand_raster_reference(skinned, hand.indices, hand.texture, view, 61, 47));
  }
  const GpuRaster empty = run_gpu_hand_raster({}, {}, hand.texture, camera);
  for (float m : empty.mask.texels) REQUIRE(m == 0.0f);
}
