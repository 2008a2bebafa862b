// ibr_warp_blend: the fused warp and lumigraph blend on the GPU against the composed references
// of ibr_warp and ibr_blend, and against the split path on the GPU, on random inputs of odd
// sizes with 1 to 6 views and k = 2 and 3. Colors to 2e-3 against the references (the warp's
// tolerance: sample positions through the float lens model differ by ~1e-3 pixel), and 1 pixel
// plus 0.1% of the covered pixels may differ where a sample lies exactly on a visibility or
// image border; against the split GPU path to 1e-5, with 1 pixel plus 0.1% allowed to differ
// (each shader is compiled on its own, so a visibility test on its border may round the other
// way). Hard cases: NaN, Inf, negative and zero fused depths, views without depth, points behind
// every camera, a single view. No NaN or Inf.
#include <limits>

#include "passes/ibr_blend.h"
#include "passes/ibr_foreground.h"
#include "passes/ibr_warp.h"
#include "passes/ibr_warp_blend.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr float kNaNIbrWarpBlend = std::numeric_limits<float>::quiet_NaN();

struct InputsIbrWarpBlend {
  HostImage fused, color, points;
};

// Views whose own depths agree with the fused surface often enough to exercise both outcomes
// of the visibility test.
InputsIbrWarpBlend random_inputs_ibr_warp_blend(std::mt19937& rng, const test::IbrRig& rig, uint32_t width, uint32_t height) {
  const uint32_t views = uint32_t(rig.cameras.size());
  InputsIbrWarpBlend in{test::random_fused_depth(rng, width, height),
            test::random_image(rng, rig.cameras[0].color.intrinsics.width,
                               rig.cameras[0].color.intrinsics.height * views, PixelFormat::RGBA8),
            passes::ibr_foreground_reference(rig.table, test::random_depth_atlas(rng, rig, 0.05f),
                                             passes::depth_ray_atlas(rig.cameras))};
  for (size_t i = 3; i < in.points.texels.size(); i += 4)
    if (in.points.texels[i] > 0.0f) in.points.texels[i] = std::uniform_real_distribution<float>(0.55f, 0.85f)(rng);
  return in;
}

passes::Portrait run_fused(const test::IbrRig& rig, const InputsIbrWarpBlend& in, const passes::BlendSettings& blend = {},
                           const passes::WarpSettings& warp = {}) {
  const passes::IbrTilesPass tiling(test::gpu());
  const passes::IbrWarpBlendPass pass(test::gpu(), uint32_t(rig.cameras.size()), warp, blend);
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_warp_blend");
  const uint32_t w = in.fused.width, h = in.fused.height;
  passes::IbrTiles tiles(test::gpu(), "surface tiles", w, h);
  vk::Image& fused = gpu.input("fused depth", in.fused);
  vk::Image& portrait = gpu.output("portrait", w, h, PixelFormat::RGBA32F);
  vk::Image& portrait_depth = gpu.output("portrait depth", w, h, PixelFormat::R32F);
  tiling.add_to(gpu.graph(), fused, tiles, {&portrait, &portrait_depth});
  pass.add_to(gpu.graph(), scene, fused, gpu.input("color", in.color), gpu.input("points", in.points), tiles, portrait,
              portrait_depth);
  const test::PassOutputs out = gpu.run();
  return {out.image("portrait"), out.image("portrait depth")};
}

passes::Portrait run_split(const test::IbrRig& rig, const InputsIbrWarpBlend& in, const passes::BlendSettings& blend) {
  const passes::IbrWarpPass warp(test::gpu());
  const passes::IbrBlendPass blending(test::gpu(), blend);
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_warp then ibr_blend");
  const uint32_t w = in.fused.width, h = in.fused.height, views = uint32_t(rig.cameras.size());
  vk::Image& fused = gpu.input("fused depth", in.fused);
  vk::Image& warped = gpu.output("warped", w, h * views, PixelFormat::RGBA32F);
  vk::Image& features = gpu.output("features", w, h * views, PixelFormat::RGBA32F);
  warp.add_to(gpu.graph(), scene, fused, gpu.input("color", in.color), gpu.input("points", in.points), warped, features,
              views);
  blending.add_to(gpu.graph(), fused, warped, features, gpu.output("portrait", w, h, PixelFormat::RGBA32F),
                  gpu.output("portrait depth", w, h, PixelFormat::R32F), views);
  const test::PassOutputs out = gpu.run();
  return {out.image("portrait"), out.image("portrait depth")};
}

size_t covered_ibr_warp_blend(const passes::Portrait& portrait) {
  size_t count = 0;
  for (size_t i = 3; i < portrait.color.texels.size(); i += 4) count += portrait.color.texels[i] > 0.0f;
  return count;
}

}  // namespace

TEST_CASE("ibr_warp_blend on random inputs, odd sizes, against the references and the split path",
          "[ibr_warp_blend][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(41);
  for (const auto& [width, height] : test::odd_sizes())
    for (uint32_t views : {1u, 2u, 4u, 6u}) {
      INFO(width << "x" << height << ", " << views << " views");
      const test::IbrRig rig = test::ibr_rig(views, 37, 21, 41, 37, width, height);
      const InputsIbrWarpBlend in = random_inputs_ibr_warp_blend(rng, rig, width, height);
      for (int k : {2, 3}) {
        INFO("k = " << k);
        passes::BlendSettings blend;
        blend.best_views = k;
        const passes::Portrait fused = run_fused(rig, in, blend);
        const passes::Portrait reference = passes::ibr_warp_blend_reference(rig.table, in.fused, in.color, in.points, {}, blend);
        const size_t pixels = size_t(width) * height, seen = covered_ibr_warp_blend(reference);
        INFO(seen << " pixels covered");
        // Every size of 500 pixels or more sees the surface here (1.2 to 9.6 % of its pixels
        // with this seed), whatever the view count: a case that covers nothing checks nothing.
        if (pixels >= 500) REQUIRE(seen >= pixels / 100);
        // Mismatches counted against the covered pixels, where the blend happens: lavapipe gives
        // none; one pixel plus 0.1 % of them leaves room for samples on a border.
        RT_REQUIRE_MOSTLY_MATCHES(fused.color, reference.color, 2e-3, 1e-5, 1 + seen / 1000);
        RT_REQUIRE_MOSTLY_MATCHES(fused.depth, reference.depth, 0.0, 1e-5, 1 + seen / 1000);
        const passes::Portrait split = run_split(rig, in, blend);
        RT_REQUIRE_MOSTLY_MATCHES(fused.color, split.color, 1e-5, 1e-5, 1 + pixels / 1000);
        RT_REQUIRE_MOSTLY_MATCHES(fused.depth, split.depth, 0.0, 1e-5, 1 + pixels / 1000);
      }
    }
}

TEST_CASE("ibr_warp_blend hard cases", "[ibr_warp_blend][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(42);
  const test::IbrRig rig = test::ibr_rig(3, 37, 21, 41, 37, 29, 19);
  const InputsIbrWarpBlend random = random_inputs_ibr_warp_blend(rng, rig, 29, 19);
  const passes::Portrait nothing{HostImage(29, 19, PixelFormat::RGBA32F, 0.0f), HostImage(29, 19, PixelFormat::R32F, 0.0f)};

  SECTION("NaN, Inf, negative and zero fused depths: alpha 0, color 0, depth 0") {
    InputsIbrWarpBlend in = random;
    const float bad[] = {kNaNIbrWarpBlend, std::numeric_limits<float>::infinity(), -1.0f, 0.0f};
    for (size_t i = 0; i < in.fused.texels.size(); ++i) in.fused.texels[i] = bad[i % 4];
    const passes::Portrait gpu = run_fused(rig, in);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.color, nothing.color, 0.0, 1e-5, 0);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.depth, nothing.depth, 0.0, 1e-5, 0);
  }
  SECTION("views without depth see nothing: alpha 0, never NaN") {
    // A tolerance of 10 m accepts any own depth against the surface, 0 included: only the test
    // that an own depth exists refuses these samples. With valid own depths everywhere the same
    // surface is seen, so the tolerance does let samples through.
    passes::WarpSettings accept_any;
    accept_any.visibility = {10.0f, 0.0f};
    InputsIbrWarpBlend in = random;
    in.points = HostImage(in.points.width, in.points.height, PixelFormat::RGBA32F, 0.7f);
    REQUIRE(covered_ibr_warp_blend(passes::ibr_warp_blend_reference(rig.table, in.fused, in.color, in.points, accept_any, {})) > 100);
    std::fill(in.points.texels.begin(), in.points.texels.end(), 0.0f);
    const passes::Portrait gpu = run_fused(rig, in, {}, accept_any);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.color, nothing.color, 0.0, 1e-5, 0);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.depth, nothing.depth, 0.0, 1e-5, 0);
    const passes::Portrait reference = passes::ibr_warp_blend_reference(rig.table, in.fused, in.color, in.points, accept_any, {});
    RT_REQUIRE_MOSTLY_MATCHES(reference.color, nothing.color, 0.0, 1e-5, 0);
  }
  SECTION("surface points behind every camera are seen by none") {
    const test::IbrRig ahead = test::turned_away(rig);
    InputsIbrWarpBlend in = random;
    in.fused = HostImage(29, 19, PixelFormat::R32F, 0.3f);
    in.points = HostImage(in.points.width, in.points.height, PixelFormat::RGBA32F, 0.7f);
    passes::WarpSettings accept_any;
    accept_any.visibility = {10.0f, 0.0f};
    const passes::Portrait gpu = run_fused(ahead, in, {}, accept_any);
    RT_REQUIRE_MOSTLY_MATCHES(gpu.color, nothing.color, 0.0, 1e-5, 0);
  }
  SECTION("one view: its warped color where it sees the surface") {
    const test::IbrRig one = test::ibr_rig(1, 37, 21, 41, 37, 29, 19);
    const InputsIbrWarpBlend in = random_inputs_ibr_warp_blend(rng, one, 29, 19);
    const passes::Portrait gpu = run_fused(one, in);
    const passes::WarpedViews warped = passes::ibr_warp_reference(one.table, in.fused, in.color, in.points);
    REQUIRE(covered_ibr_warp_blend(gpu) > 0);
    // With one candidate its weight is its feather over itself: the color is the sample's.
    RT_REQUIRE_MOSTLY_MATCHES(gpu.color, warped.warped, 2e-3, 1e-5, 1 + 29 * 19 / 200);
  }
}

TEST_CASE("ibr_warp_blend refuses a view count it cannot hold", "[ibr_warp_blend][gpu]") {
  REQUIRE_THROWS_WITH(passes::IbrWarpBlendPass(test::gpu(), 0), Catch::Contains("1 to 6 views"));
  REQUIRE_THROWS_WITH(passes::IbrWarpBlendPass(test::gpu(), RT_IBR_MAX_VIEWS + 1), Catch::Contains("1 to 6 views"));
}
