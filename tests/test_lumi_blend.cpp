// lumi_blend: GPU against the C++ reference on random warped views and random weights of odd sizes
// (1x1, a row, a column, 641x359), 1 to 6 views, to 1e-5 absolute + 1e-5 relative, depths
// exactly; by hand: the weights renormalised over the views that see the pixel, all-zero weights
// shared equally, NaN and negative weights and NaN alpha, no view seeing (alpha 0, depth 0).
// No NaN or Inf.
#include <limits>
#include <random>

#include "passes/lumi_blend.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

constexpr float kNaNLumiBlend = std::numeric_limits<float>::quiet_NaN();

passes::Portrait run_blend_lumi_blend(const HostImage& fused, const HostImage& warped, const HostImage& features,
                           const passes::LumiTensor& blending, uint32_t views) {
  const passes::LumiBlendPass pass(test::gpu());
  test::PassHarness gpu("lumi_blend");
  pass.add_to(gpu.graph(), gpu.input("fused depth", fused), gpu.input("warped", warped), gpu.input("features", features),
              test::input_tensor(gpu, "blending", blending),
              gpu.output("portrait", fused.width, fused.height, PixelFormat::RGBA32F),
              gpu.output("portrait depth", fused.width, fused.height, PixelFormat::R32F), views);
  const test::PassOutputs out = gpu.run();
  return {out.image("portrait"), out.image("portrait depth")};
}

}  // namespace

TEST_CASE("lumi_blend on random views and weights, odd sizes", "[lumi_blend][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(37);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const auto& [width, height] : test::odd_sizes())
    for (uint32_t views : {1u, 2u, 4u, 6u}) {
      INFO(width << "x" << height << ", " << views << " views");
      const HostImage fused = test::random_fused_depth(rng, width, height);
      const HostImage warped = test::random_image(rng, width, height * views, PixelFormat::RGBA32F);
      HostImage features = test::random_image(rng, width, height * views, PixelFormat::RGBA32F);
      for (size_t i = 0; i < features.texels.size(); i += 4) features.texels[i + 3] = unit(rng) < 0.7f ? 1.0f : 0.0f;
      passes::LumiTensor blending = passes::random_lumi_tensor(rng, 1, 1 + views, width, height, 0.0f, 1.0f);
      for (float& b : blending.values)
        if (unit(rng) < 0.05f) b = 0.0f;
      const passes::Portrait gpu = run_blend_lumi_blend(fused, warped, features, blending, views);
      const passes::Portrait reference = passes::lumi_blend_reference(fused, warped, features, blending, views);
      RT_REQUIRE_MATCHES(gpu.color, reference.color, 1e-5, 1e-5);
      RT_REQUIRE_MATCHES(gpu.depth, reference.depth, 0.0, 0.0);
    }
}

TEST_CASE("lumi_blend hard cases", "[lumi_blend][gpu]") {
  test::NoValidationErrors no_errors;
  // Two views, one pixel: view colors red and green; each case sets which see and the weights.
  auto run = [](bool sees0, bool sees1, float w0, float w1, float alpha) {
    const HostImage fused(1, 1, PixelFormat::R32F, 1.25f);
    HostImage warped(1, 2, PixelFormat::RGBA32F, 0.0f), features(1, 2, PixelFormat::RGBA32F, 0.0f);
    warped.at(0, 0, 0) = 1.0f;
    warped.at(0, 1, 1) = 1.0f;
    const bool sees[2] = {sees0, sees1};
    for (uint32_t v = 0; v < 2; ++v)
      if (sees[v]) features.at(0, v, 2) = 1.0f, features.at(0, v, 3) = 1.0f;
    passes::LumiTensor blending(1, 3, 1, 1);
    blending.at(0, 0, 0, 0) = alpha;
    blending.at(0, 1, 0, 0) = w0;
    blending.at(0, 2, 0, 0) = w1;
    const passes::Portrait gpu = run_blend_lumi_blend(fused, warped, features, blending, 2);
    const passes::Portrait reference = passes::lumi_blend_reference(fused, warped, features, blending, 2);
    RT_REQUIRE_MATCHES(gpu.color, reference.color, 1e-6, 1e-6);
    RT_REQUIRE_MATCHES(gpu.depth, reference.depth, 0.0, 0.0);
    return gpu;
  };
  SECTION("both see: the weights blend, alpha is the network's") {
    const passes::Portrait p = run(true, true, 0.25f, 0.75f, 0.8f);
    REQUIRE(p.color.at(0, 0, 0) == Approx(0.25f).epsilon(1e-6));
    REQUIRE(p.color.at(0, 0, 1) == Approx(0.75f).epsilon(1e-6));
    REQUIRE(p.color.at(0, 0, 3) == Approx(0.8f).epsilon(1e-6));
    REQUIRE(p.depth.at(0, 0) == 1.25f);
  }
  SECTION("a view's weight where it does not see goes to the views that do") {
    const passes::Portrait p = run(false, true, 0.9f, 0.1f, 1.0f);
    REQUIRE(p.color.at(0, 0, 0) == 0.0f);
    REQUIRE(p.color.at(0, 0, 1) == Approx(1.0f).epsilon(1e-6));
  }
  SECTION("zero, negative and NaN weights: the seeing views share equally") {
    const passes::Portrait p = run(true, true, kNaNLumiBlend, -1.0f, 1.0f);
    REQUIRE(p.color.at(0, 0, 0) == Approx(0.5f).epsilon(1e-6));
    REQUIRE(p.color.at(0, 0, 1) == Approx(0.5f).epsilon(1e-6));
  }
  SECTION("NaN alpha gives alpha 0, never NaN") {
    REQUIRE(run(true, false, 1.0f, 0.0f, kNaNLumiBlend).color.at(0, 0, 3) == 0.0f);
  }
  SECTION("no view sees: empty portrait and no depth") {
    const passes::Portrait p = run(false, false, 0.5f, 0.5f, 1.0f);
    for (uint32_t c = 0; c < 4; ++c) REQUIRE(p.color.at(0, 0, c) == 0.0f);
    REQUIRE(p.depth.at(0, 0) == 0.0f);
  }
}
