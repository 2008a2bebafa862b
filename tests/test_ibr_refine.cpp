// ibr_refine (plane sweep): GPU against the C++ reference. The winner among hypotheses is an
// argmin of color variances; two hypotheses within float rounding of each other may swap, so at
// most 1% of pixels, rounded down, may pick another hypothesis (stated tolerance; none in an
// image of fewer than 100 pixels, so that no small image can be wrong); the rest match to 1e-5.
// Only views that see a point score it (warping's visibility test on each view's own depth).
#include "passes/ibr_refine.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

// Each view's own depth (w of the points atlas, 9x7 per view): `own_depth` everywhere, or random
// in 0.3-1.2 m with a fifth of the texels invalid when `own_depth` is negative.
HostImage points_atlas(std::mt19937& rng, const test::IbrRig& rig, float own_depth) {
  HostImage points(9, 7 * uint32_t(rig.cameras.size()), PixelFormat::RGBA32F, 0.0f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (size_t i = 3; i < points.texels.size(); i += 4)
    points.texels[i] = own_depth >= 0.0f ? own_depth : unit(rng) < 0.2f ? 0.0f : 0.3f + 0.9f * unit(rng);
  return points;
}

// A tolerance that accepts any valid own depth, to test the sweep apart from occlusion.
constexpr passes::VisibilityTolerance kSeesEveryValidDepth{10.0f, 0.01f};

HostImage run_gpu_ibr_refine(const test::IbrRig& rig, const HostImage& fused, const HostImage& color, const HostImage& points,
                  const passes::RefineSettings& settings, passes::VisibilityTolerance visibility) {
  const passes::IbrRefinePass pass(test::gpu(), settings, visibility);
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_refine");
  pass.add_to(gpu.graph(), scene, gpu.input("fused depth", fused), gpu.input("color", color), gpu.input("points", points),
              gpu.output("refined depth", fused.width, fused.height, PixelFormat::R32F), uint32_t(rig.cameras.size()));
  return gpu.run().image("refined depth");
}

}  // namespace

TEST_CASE("ibr_refine on random inputs, odd sizes", "[ibr_refine][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(41);
  size_t moved = 0;
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const test::IbrRig rig = test::ibr_rig(3, 37, 21, 9, 7, width, height);
    HostImage fused = test::random_image(rng, width, height, PixelFormat::R32F, 1.3f, 1.5f);
    for (size_t i = 0; i < fused.texels.size(); i += 5) fused.texels[i] = 0.0f;
    const HostImage color = test::random_image(rng, 37, 63, PixelFormat::RGBA8);
    const HostImage points = points_atlas(rng, rig, -1.0f);
    const passes::RefineSettings settings;
    const HostImage gpu = run_gpu_ibr_refine(rig, fused, color, points, settings, kSeesEveryValidDepth);
    const HostImage reference =
        passes::ibr_refine_reference(rig.table, fused, color, points, settings, kSeesEveryValidDepth);
    const auto comparison = test::compare_pixels(gpu, reference, 1e-5, 1e-5);
    REQUIRE(comparison.non_finite == 0);
    INFO(comparison.mismatched_pixels << " pixels differ, max " << comparison.max_abs_error);
    REQUIRE(comparison.mismatched_pixels <= size_t(width) * height / 100);
    for (size_t i = 0; i < fused.texels.size(); ++i) {
      REQUIRE(std::abs(gpu.texels[i] - fused.texels[i]) <= 4 * settings.step_m + 1e-5f);  // within the sweep
      moved += gpu.texels[i] != fused.texels[i];
    }
  }
  REQUIRE(moved > 0);  // the sweep does move depths on random colors
}

TEST_CASE("ibr_refine hard cases", "[ibr_refine][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(42);
  const test::IbrRig rig = test::ibr_rig(2, 37, 21, 9, 7, 13, 11);
  const HostImage seen_everywhere = points_atlas(rng, rig, 0.7f);
  SECTION("uniform color: every hypothesis ties, the fused depth stays") {
    const HostImage fused = test::random_image(rng, 13, 11, PixelFormat::R32F, 1.3f, 1.5f);
    const HostImage grey(37, 42, PixelFormat::RGBA8, 0.5f);
    RT_REQUIRE_MATCHES(run_gpu_ibr_refine(rig, fused, grey, seen_everywhere, {}, kSeesEveryValidDepth), fused, 0.0, 0.0);
  }
  SECTION("occluded views do not score: with an occluder 10 cm before each camera the depth stays") {
    const HostImage fused = test::random_image(rng, 13, 11, PixelFormat::R32F, 1.3f, 1.5f);
    const HostImage color = test::random_image(rng, 37, 42, PixelFormat::RGBA8);
    const HostImage moved = run_gpu_ibr_refine(rig, fused, color, seen_everywhere, {}, kSeesEveryValidDepth);
    REQUIRE(moved.texels != fused.texels);  // the same colors do move depths where the views see
    const HostImage occluded = points_atlas(rng, rig, 0.1f);
    RT_REQUIRE_MATCHES(run_gpu_ibr_refine(rig, fused, color, occluded, {}, {}), fused, 0.0, 0.0);
    RT_REQUIRE_MATCHES(passes::ibr_refine_reference(rig.table, fused, color, occluded), fused, 0.0, 0.0);
  }
  SECTION("no depth stays no depth; one hypothesis is the identity") {
    HostImage fused(13, 11, PixelFormat::R32F, 0.0f);
    fused.at(3, 3) = 1.4f;
    passes::RefineSettings one;
    one.hypotheses = 1;
    RT_REQUIRE_MATCHES(run_gpu_ibr_refine(rig, fused, test::random_image(rng, 37, 42, PixelFormat::RGBA8), seen_everywhere, one,
                               kSeesEveryValidDepth),
                       fused, 0.0, 0.0);
  }
  SECTION("bad settings are refused") {
    passes::RefineSettings bad;
    bad.hypotheses = 0;
    REQUIRE_THROWS_WITH(passes::IbrRefinePass(test::gpu(), bad), Catch::Contains("hypotheses"));
    REQUIRE_THROWS_WITH(passes::IbrRefinePass(test::gpu(), {}, {0.03f, -0.01f}), Catch::Contains("visibility"));
    HostImage odd_points(9, 15, PixelFormat::RGBA32F, 0.0f);  // not two bands
    REQUIRE_THROWS_WITH(run_gpu_ibr_refine(rig, HostImage(13, 11, PixelFormat::R32F, 1.4f),
                                test::random_image(rng, 37, 42, PixelFormat::RGBA8), odd_points, {}, {}),
                        Catch::Contains("bands"));
  }
}
