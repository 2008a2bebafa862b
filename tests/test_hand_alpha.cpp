// hand_alpha pass (paper Eq. 4): GPU against the C++ reference.
// Tolerance: 1e-6 absolute + 1e-6 relative (float arithmetic, possibly contracted to FMA).
#include <limits>

#include "passes/hand_alpha.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr double kAbs = 1e-6, kRel = 1e-6;

HostImage run_gpu_hand_alpha(const HostImage& mask, float distance, passes::FusionRamp ramp = {}) {
  const passes::HandAlphaPass pass(test::gpu(), ramp);
  test::PassHarness gpu("hand_alpha");
  pass.add_to(gpu.graph(), gpu.input("hand mask", mask),
              gpu.output("hand alpha", mask.width, mask.height, PixelFormat::R32F), [distance] { return distance; });
  return gpu.run().image("hand alpha");
}

}  // namespace

TEST_CASE("hand_alpha reference follows Eq. 4", "[hand_alpha]") {
  const passes::FusionRamp ramp;
  CHECK(passes::hand_alpha_of_distance(0.2f, ramp) == 1.0f);
  CHECK(passes::hand_alpha_of_distance(0.4f, ramp) == 0.0f);
  CHECK(passes::hand_alpha_of_distance(0.3f, ramp) == Approx(0.5f).margin(1e-6));
  CHECK(passes::hand_alpha_of_distance(0.35f, ramp) == Approx(0.25f).margin(1e-6));
  CHECK(passes::hand_alpha_of_distance(0.05f, ramp) == 1.0f);  // clipped at d_min
  CHECK(passes::hand_alpha_of_distance(2.0f, ramp) == 0.0f);   // clipped at d_max
  CHECK(passes::hand_alpha_of_distance(std::numeric_limits<float>::quiet_NaN(), ramp) == 0.0f);
}

TEST_CASE("hand_alpha on random masks of odd sizes", "[hand_alpha][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> distance(0.0f, 0.6f);
  for (const auto& [width, height] : test::odd_sizes()) {
    const HostImage mask = test::random_image(rng, width, height, PixelFormat::R32F);
    const float d = distance(rng);
    INFO(width << "x" << height << ", d = " << d);
    RT_REQUIRE_MATCHES(run_gpu_hand_alpha(mask, d), passes::hand_alpha_reference(mask, d), kAbs, kRel);
  }
}

TEST_CASE("hand_alpha hard distances: d_min, d_max, NaN, infinities, negative, huge", "[hand_alpha][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(3);
  const HostImage mask = test::random_image(rng, 7, 5, PixelFormat::R32F);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (float d : {0.2f, 0.4f, nan, inf, -inf, -0.3f, 0.0f, 1e30f, -1e30f, std::numeric_limits<float>::max(),
                  std::numeric_limits<float>::denorm_min()}) {
    INFO("d = " << d);
    const HostImage gpu = run_gpu_hand_alpha(mask, d);
    RT_REQUIRE_MATCHES(gpu, passes::hand_alpha_reference(mask, d), kAbs, kRel);
  }
  // No hand (NaN) and far hands give alpha 0 everywhere; a hand at the glass gives the mask.
  const HostImage full = test::filled_image(9, 1, PixelFormat::R32F, 1.0f);
  RT_REQUIRE_MATCHES(run_gpu_hand_alpha(full, nan), test::filled_image(9, 1, PixelFormat::R32F, 0.0f), 0.0, 0.0);
  RT_REQUIRE_MATCHES(run_gpu_hand_alpha(full, inf), test::filled_image(9, 1, PixelFormat::R32F, 0.0f), 0.0, 0.0);
  RT_REQUIRE_MATCHES(run_gpu_hand_alpha(full, 0.0f), full, 0.0, 0.0);
}

TEST_CASE("hand_alpha hard masks: zero, one, NaN, Inf, out of range", "[hand_alpha][gpu]") {
  test::NoValidationErrors no_errors;
  for (float value : {0.0f, 1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                      -std::numeric_limits<float>::infinity(), -0.5f, 3.0f}) {
    INFO("mask value " << value);
    const HostImage mask = test::filled_image(33, 17, PixelFormat::R32F, value);
    RT_REQUIRE_MATCHES(run_gpu_hand_alpha(mask, 0.25f), passes::hand_alpha_reference(mask, 0.25f), kAbs, kRel);
  }
}

TEST_CASE("hand_alpha ramp is a knob set by name", "[hand_alpha][gpu]") {
  test::NoValidationErrors no_errors;
  const passes::FusionRamp ramp{0.1f, 0.3f};
  std::mt19937 rng(4);
  const HostImage mask = test::random_image(rng, 641, 359, PixelFormat::R32F);
  for (float d : {0.1f, 0.15f, 0.2f, 0.3f}) {
    INFO("d = " << d);
    RT_REQUIRE_MATCHES(run_gpu_hand_alpha(mask, d, ramp), passes::hand_alpha_reference(mask, d, ramp), kAbs, kRel);
  }
  CHECK_THROWS_WITH(passes::HandAlphaPass(test::gpu(), {0.4f, 0.2f}), Catch::Contains("d_min < d_max"));
  CHECK_THROWS_WITH(passes::HandAlphaPass(test::gpu(), {0.3f, 0.3f}), Catch::Contains("d_min < d_max"));
  CHECK_THROWS(passes::HandAlphaPass(test::gpu(), {std::numeric_limits<float>::quiet_NaN(), 0.3f}));
}
