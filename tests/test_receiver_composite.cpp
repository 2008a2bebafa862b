// receiver_composite: the receiver's three equations in one pass, on the GPU against the three
// references composed and against the three passes run one after the other on the GPU, on
// random layers of odd sizes at distances across the ramp. The output is 8-bit: one step
// (1/255) for the GPU's float-to-unorm rounding against the references; against the GPU's own
// three passes one step too, where a pixel on a rounding edge is computed by two separately
// compiled shaders. Hard cases: NaN and infinite distances and layers, colors and alphas out of
// [0, 1] in every layer, zero alpha everywhere, a 1x1 frame. No NaN or Inf.
#include <limits>

#include "passes/composite.h"
#include "passes/hand_alpha.h"
#include "passes/overlay.h"
#include "passes/receiver_composite.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr double kOneStepReceiverComposite = 1.0 / 255.0 + 1e-6;
constexpr float kNaNReceiverComposite = std::numeric_limits<float>::quiet_NaN();
constexpr float kInfReceiverComposite = std::numeric_limits<float>::infinity();

struct LayersReceiverComposite {
  HostImage hand_mask, hand_color, portrait, background;
};

LayersReceiverComposite random_layers_receiver_composite(std::mt19937& rng, uint32_t w, uint32_t h) {
  return {test::random_image(rng, w, h, PixelFormat::R32F), test::random_image(rng, w, h, PixelFormat::RGBA32F),
          test::random_image(rng, w, h, PixelFormat::RGBA32F), test::random_image(rng, w, h, PixelFormat::RGBA32F)};
}

HostImage run_one_pass(const LayersReceiverComposite& in, float distance) {
  const passes::ReceiverCompositePass pass(test::gpu());
  test::PassHarness gpu("receiver_composite");
  const uint32_t w = in.portrait.width, h = in.portrait.height;
  pass.add_to(gpu.graph(), gpu.input("hand mask", in.hand_mask), gpu.input("hand color", in.hand_color),
              gpu.input("portrait", in.portrait), gpu.input("background", in.background),
              gpu.output("display", w, h, PixelFormat::RGBA8), [distance] { return distance; });
  return gpu.run().image("display");
}

HostImage run_three_passes(const LayersReceiverComposite& in, float distance) {
  const passes::HandAlphaPass hand_alpha(test::gpu());
  const passes::OverlayPass overlay(test::gpu());
  const passes::CompositePass composite(test::gpu());
  test::PassHarness gpu("hand_alpha, overlay, composite");
  const uint32_t w = in.portrait.width, h = in.portrait.height;
  vk::Image& alpha = gpu.output("hand alpha", w, h, PixelFormat::R32F);
  vk::Image& fused = gpu.output("fused", w, h, PixelFormat::RGBA32F);
  hand_alpha.add_to(gpu.graph(), gpu.input("hand mask", in.hand_mask), alpha, [distance] { return distance; });
  overlay.add_to(gpu.graph(), gpu.input("hand color", in.hand_color), alpha, gpu.input("portrait", in.portrait), fused);
  composite.add_to(gpu.graph(), fused, gpu.input("background", in.background),
                   gpu.output("display", w, h, PixelFormat::RGBA8));
  return gpu.run().image("display");
}

void require_both_agree(const LayersReceiverComposite& in, float distance) {
  INFO("distance " << distance << " m");
  const HostImage gpu = run_one_pass(in, distance);
  const HostImage reference = passes::receiver_composite_reference(in.hand_mask, in.hand_color, in.portrait,
                                                                   in.background, distance);
  RT_REQUIRE_MATCHES(gpu, reference, kOneStepReceiverComposite, 0.0);
  RT_REQUIRE_MATCHES(gpu, run_three_passes(in, distance), kOneStepReceiverComposite, 0.0);
}

}  // namespace

TEST_CASE("receiver_composite on random layers of odd sizes across the ramp", "[receiver_composite][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(17);
  const passes::FusionRamp ramp;
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const LayersReceiverComposite in = random_layers_receiver_composite(rng, width, height);
    for (float distance : {0.0f, ramp.d_min_m, 0.5f * (ramp.d_min_m + ramp.d_max_m), ramp.d_max_m, 1.5f})
      require_both_agree(in, distance);
  }
}

TEST_CASE("receiver_composite follows Eq. 4's linear ramp between d_min and d_max", "[receiver_composite][gpu]") {
  // The reference shares the ramp's formula, so agreeing with it proves nothing about the ramp:
  // here the expected frame is computed from the equation. A full mask over an opaque portrait
  // makes the display c_g alpha + c_i (1 - alpha); a quarter and three quarters of the way are
  // where a smoothstep or another curve through the same ends and midpoint departs from it.
  test::NoValidationErrors no_errors;
  std::mt19937 rng(19);
  const passes::FusionRamp ramp;
  LayersReceiverComposite in = random_layers_receiver_composite(rng, 13, 7);
  in.hand_mask = test::filled_image(13, 7, PixelFormat::R32F, 1.0f);
  for (size_t i = 3; i < in.portrait.texels.size(); i += 4) in.portrait.texels[i] = 1.0f;
  for (const float along : {0.25f, 0.75f}) {
    const float distance = ramp.d_min_m + along * (ramp.d_max_m - ramp.d_min_m);
    const float alpha = 1.0f - along;
    INFO("distance " << distance << " m, alpha " << alpha);
    HostImage expected(13, 7, PixelFormat::RGBA8);
    for (uint32_t y = 0; y < 7; ++y)
      for (uint32_t x = 0; x < 13; ++x) {
        for (uint32_t c = 0; c < 3; ++c)
          expected.at(x, y, c) = in.hand_color.at(x, y, c) * alpha + in.portrait.at(x, y, c) * (1.0f - alpha);
        expected.at(x, y, 3) = 1.0f;
      }
    RT_REQUIRE_MATCHES(run_one_pass(in, distance), expected, kOneStepReceiverComposite, 0.0);
    RT_REQUIRE_MATCHES(run_three_passes(in, distance), expected, kOneStepReceiverComposite, 0.0);
  }
}

TEST_CASE("receiver_composite hard cases", "[receiver_composite][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(18);
  const passes::FusionRamp ramp;
  const float inside_ramp = 0.5f * (ramp.d_min_m + ramp.d_max_m);

  SECTION("NaN and infinite distances: no geometry hand, the portrait over the background") {
    const LayersReceiverComposite in = random_layers_receiver_composite(rng, 13, 7);
    LayersReceiverComposite no_hand = in;
    no_hand.hand_mask = test::filled_image(13, 7, PixelFormat::R32F, 0.0f);
    for (float distance : {kNaNReceiverComposite, kInfReceiverComposite, -kInfReceiverComposite}) {
      require_both_agree(in, distance);
      RT_REQUIRE_MATCHES(run_one_pass(in, distance), run_one_pass(no_hand, inside_ramp), kOneStepReceiverComposite, 0.0);
    }
  }
  SECTION("zero alpha everywhere shows the background") {
    LayersReceiverComposite in = random_layers_receiver_composite(rng, 13, 7);
    in.hand_mask = test::filled_image(13, 7, PixelFormat::R32F, 0.0f);
    for (size_t i = 3; i < in.portrait.texels.size(); i += 4) in.portrait.texels[i] = 0.0f;
    HostImage opaque_background = in.background;
    for (size_t i = 3; i < opaque_background.texels.size(); i += 4) opaque_background.texels[i] = 1.0f;
    require_both_agree(in, inside_ramp);
    RT_REQUIRE_MATCHES(run_one_pass(in, inside_ramp), opaque_background, kOneStepReceiverComposite, 0.0);
  }
  SECTION("NaN, infinite and out-of-range layers stay in range") {
    LayersReceiverComposite in = random_layers_receiver_composite(rng, 11, 5);
    const float bad[] = {kNaNReceiverComposite, kInfReceiverComposite, -kInfReceiverComposite, -1.0f, 5.0f};
    for (HostImage* image : {&in.hand_mask, &in.hand_color, &in.portrait, &in.background})
      for (size_t i = 0; i < image->texels.size(); i += 3) image->texels[i] = bad[(i / 3) % 5];
    for (float distance : {0.0f, inside_ramp, kNaNReceiverComposite}) require_both_agree(in, distance);
  }
  SECTION("a 1x1 frame") {
    require_both_agree(random_layers_receiver_composite(rng, 1, 1), inside_ramp);
  }
}
