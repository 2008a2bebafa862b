// overlay pass (paper Eq. 5): GPU against the C++ reference, which divides by alpha_f as the
// paper prints it and premultiplies after. Tolerance: 1e-5 absolute + 1e-5 relative.
#include <limits>

#include "passes/overlay.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr double kAbsOverlay = 1e-5, kRel = 1e-5;

struct Layers {
  HostImage hand_color, hand_alpha, portrait;
};

HostImage run_gpu_overlay(const Layers& in) {
  const passes::OverlayPass pass(test::gpu());
  test::PassHarness gpu("overlay");
  pass.add_to(gpu.graph(), gpu.input("hand color", in.hand_color), gpu.input("hand alpha", in.hand_alpha),
              gpu.input("portrait", in.portrait),
              gpu.output("fused", in.portrait.width, in.portrait.height, PixelFormat::RGBA32F));
  return gpu.run().image("fused");
}

Layers random_layers(std::mt19937& rng, uint32_t w, uint32_t h) {
  return {test::random_image(rng, w, h, PixelFormat::RGBA32F), test::random_image(rng, w, h, PixelFormat::R32F),
          test::random_image(rng, w, h, PixelFormat::RGBA32F)};
}

}  // namespace

TEST_CASE("overlay reference follows Eq. 5", "[overlay]") {
  Layers in{HostImage(1, 1, PixelFormat::RGBA32F), HostImage(1, 1, PixelFormat::R32F), HostImage(1, 1, PixelFormat::RGBA32F)};
  in.hand_color.texels = {1.0f, 0.5f, 0.0f, 1.0f};
  in.hand_alpha.texels = {0.25f};
  in.portrait.texels = {0.0f, 0.5f, 1.0f, 0.8f};
  const HostImage fused = passes::overlay_reference(in.hand_color, in.hand_alpha, in.portrait);
  // alpha_f = 0.25 + 0.8 * 0.75 = 0.85; premultiplied c = c_g 0.25 + c_i 0.6
  CHECK(fused.at(0, 0, 3) == Approx(0.85f));
  CHECK(fused.at(0, 0, 0) == Approx(0.25f));
  CHECK(fused.at(0, 0, 1) == Approx(0.5f * 0.25f + 0.5f * 0.6f));
  CHECK(fused.at(0, 0, 2) == Approx(0.6f));
}

TEST_CASE("overlay on random layers of odd sizes", "[overlay][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(5);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const Layers in = random_layers(rng, width, height);
    RT_REQUIRE_MATCHES(run_gpu_overlay(in), passes::overlay_reference(in.hand_color, in.hand_alpha, in.portrait), kAbsOverlay, kRel);
  }
}

TEST_CASE("overlay hard cases: alpha 0 and 1 everywhere, non-finite inputs", "[overlay][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(6);
  const uint32_t w = 7, h = 5;
  Layers in = random_layers(rng, w, h);

  SECTION("both alphas 0: alpha_f = 0 gives (0, 0, 0, 0), not 0/0") {
    in.hand_alpha = test::filled_image(w, h, PixelFormat::R32F, 0.0f);
    for (uint32_t i = 3; i < in.portrait.texels.size(); i += 4) in.portrait.texels[i] = 0.0f;
    RT_REQUIRE_MATCHES(run_gpu_overlay(in), test::filled_image(w, h, PixelFormat::RGBA32F, 0.0f), 0.0, 0.0);
  }
  SECTION("hand alpha 1: the hand hides the portrait") {
    in.hand_alpha = test::filled_image(w, h, PixelFormat::R32F, 1.0f);
    HostImage expected = in.hand_color;
    for (uint32_t i = 3; i < expected.texels.size(); i += 4) expected.texels[i] = 1.0f;
    RT_REQUIRE_MATCHES(run_gpu_overlay(in), expected, kAbsOverlay, kRel);
  }
  SECTION("hand alpha 0, portrait alpha 1: the portrait alone") {
    in.hand_alpha = test::filled_image(w, h, PixelFormat::R32F, 0.0f);
    for (uint32_t i = 3; i < in.portrait.texels.size(); i += 4) in.portrait.texels[i] = 1.0f;
    RT_REQUIRE_MATCHES(run_gpu_overlay(in), in.portrait, kAbsOverlay, kRel);
  }
  SECTION("NaN and Inf in every input count as 0") {
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(), -2.0f, 7.0f};
    for (size_t i = 0; i < in.hand_color.texels.size(); i += 3) in.hand_color.texels[i] = bad[i % 5];
    for (size_t i = 0; i < in.hand_alpha.texels.size(); i += 2) in.hand_alpha.texels[i] = bad[i % 5];
    for (size_t i = 1; i < in.portrait.texels.size(); i += 3) in.portrait.texels[i] = bad[i % 5];
    RT_REQUIRE_MATCHES(run_gpu_overlay(in), passes::overlay_reference(in.hand_color, in.hand_alpha, in.portrait), kAbsOverlay, kRel);
  }
}
