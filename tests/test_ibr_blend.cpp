// ibr_blend: GPU against the C++ reference from given warped and feature atlases (random ones
// of odd sizes, 1 to 6 views, k = 2 and 3) to 1e-5, depths exactly; and the weights by hand:
// Buehler et al.'s 1 - p / p_k, a single visible view, none, equal penalties, NaN features.
// No NaN or Inf.
#include <array>
#include <limits>
#include <utility>

#include "passes/ibr_blend.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr float kNaNIbrBlend = std::numeric_limits<float>::quiet_NaN();

passes::Portrait run_blend(const HostImage& fused, const HostImage& warped, const HostImage& features, uint32_t views,
                           const passes::BlendSettings& settings = {}) {
  const passes::IbrBlendPass pass(test::gpu(), settings);
  test::PassHarness gpu("ibr_blend");
  pass.add_to(gpu.graph(), gpu.input("fused depth", fused), gpu.input("warped", warped), gpu.input("features", features),
              gpu.output("portrait", fused.width, fused.height, PixelFormat::RGBA32F),
              gpu.output("portrait depth", fused.width, fused.height, PixelFormat::R32F), views);
  const test::PassOutputs out = gpu.run();
  return {out.image("portrait"), out.image("portrait depth")};
}

}  // namespace

TEST_CASE("ibr_blend on random atlases, odd sizes", "[ibr_blend][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(33);
  for (const auto& [width, height] : test::odd_sizes()) {
    for (uint32_t views : {1u, 2u, 4u, 6u}) {
      INFO(width << "x" << height << ", " << views << " views");
      const HostImage fused = test::random_fused_depth(rng, width, height);
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
        views_with({{kNaNIbrBlend, 0.5f, 2.0f, 1}, {0.1f, 0.1f, 0.1f, 1}}, {{kNaNIbrBlend, 0, 1, 1}, {0.3f, kNaNIbrBlend, 1, 1}});
    const passes::Portrait gpu = run_blend(fused, warped, features, 2);
    RT_REQUIRE_MATCHES(gpu.color, passes::ibr_blend_reference(fused, warped, features, 2).color, 1e-6, 0.0);
    REQUIRE(gpu.color.at(0, 0, 3) == 0.0f);
  }
}
