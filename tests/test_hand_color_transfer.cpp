// hand_color_transfer (paper Eq. 3 on the texture): GPU against the reference on random
// textures of odd sizes with random statistics, and the hard cases: no statistics yet (T' = T),
// sigma_g at zero (the floor), black and saturated texels, a state that would overflow.
// Tolerance: 2e-3 absolute (float exp/log against double), never NaN.
#include <limits>
#include <random>

#include "passes/hand_color_transfer.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::AppearanceState;

namespace {

HostImage run_gpu_hand_color_transfer(const HostImage& texture, const AppearanceState& state, float max_contrast = passes::kMaxContrast) {
  const passes::HandColorTransferPass pass(test::gpu(), max_contrast);
  test::PassHarness gpu("hand_color_transfer");
  pass.add_to(gpu.graph(), gpu.input("template texture", texture),
              gpu.input_buffer("appearance state", std::span(&state, 1)),
              gpu.output("adapted texture", texture.width, texture.height, PixelFormat::RGBA32F));
  return gpu.run().image("adapted texture");
}

AppearanceState random_state(std::mt19937& rng) {
  std::uniform_real_distribution<float> mean(-0.8f, 0.0f), chroma(-0.1f, 0.1f), sigma(0.0f, 0.15f);
  AppearanceState s{};
  s.header = {1.0f, 1.0f, 100.0f, 0.0f};
  s.image_mean = {mean(rng), chroma(rng), chroma(rng), 0.0f};
  s.mesh_mean = {mean(rng), chroma(rng), chroma(rng), 0.0f};
  s.image_sigma = {sigma(rng), sigma(rng), sigma(rng), 0.0f};
  s.mesh_sigma = {sigma(rng), sigma(rng), sigma(rng), 0.0f};
  return s;
}

}  // namespace

TEST_CASE("hand_color_transfer matches the reference on random textures and statistics") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(13);
  for (auto [w, h] : test::odd_sizes()) {
    INFO(w << "x" << h);
    const HostImage texture = test::random_image(rng, w, h, PixelFormat::RGBA32F);
    const AppearanceState state = random_state(rng);
    RT_REQUIRE_MATCHES(run_gpu_hand_color_transfer(texture, state), passes::color_transfer_reference(texture, state, passes::kSigmaFloor), 2e-3, 0.0);
  }
}

TEST_CASE("hand_color_transfer hard cases") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(2);
  HostImage texture = test::random_image(rng, 19, 7, PixelFormat::RGBA32F);
  for (uint32_t x = 0; x < 19; ++x)
    for (uint32_t c = 0; c < 3; ++c) {
      texture.at(x, 0, c) = 0.0f;
      texture.at(x, 1, c) = 1.0f;
    }
  SECTION("no statistics yet: T' = T") {
    RT_REQUIRE_MATCHES(run_gpu_hand_color_transfer(texture, AppearanceState{}), texture, 0.0, 0.0);
  }
  SECTION("sigma_g of zero is floored; huge ratios saturate instead of overflowing") {
    AppearanceState state = random_state(rng);
    state.mesh_sigma = {0.0f, 0.0f, 0.0f, 0.0f};
    state.image_sigma = {50.0f, 50.0f, 50.0f, 0.0f};
    RT_REQUIRE_MATCHES(run_gpu_hand_color_transfer(texture, state), passes::color_transfer_reference(texture, state, passes::kSigmaFloor), 2e-3, 0.0);
  }
  SECTION("a NaN in the statistics keeps the template texture") {
    AppearanceState state = random_state(rng);
    state.image_mean[0] = std::numeric_limits<float>::quiet_NaN();
    const HostImage gpu = run_gpu_hand_color_transfer(texture, state);
    REQUIRE(test::count_non_finite(gpu) == 0);
    RT_REQUIRE_MATCHES(gpu, texture, 0.0, 0.0);
  }
}

TEST_CASE("hand_color_transfer caps the contrast: the template's detail is stretched at most max_contrast times") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(5);
  const HostImage texture = test::random_image(rng, 23, 9, PixelFormat::RGBA32F);
  AppearanceState state = random_state(rng);
  state.mesh_sigma = {0.05f, 0.01f, 0.02f, 0.0f};
  state.image_sigma = {0.5f, 0.004f, 0.2f, 0.0f};  // ratios 10, 0.4, 10
  for (float cap : {0.5f, 1.0f, 4.0f}) {
    INFO("max_contrast " << cap);
    RT_REQUIRE_MATCHES(run_gpu_hand_color_transfer(texture, state, cap), passes::color_transfer_reference(texture, state, passes::kSigmaFloor, cap),
                       2e-3, 0.0);
  }
  // At a cap of 1 a channel whose ratio is above it keeps the template's spread: the same as an
  // image sigma equal to the mesh's, while the channel below the cap is untouched by it.
  AppearanceState same_spread = state;
  same_spread.image_sigma[0] = state.mesh_sigma[0];
  same_spread.image_sigma[2] = state.mesh_sigma[2];
  RT_REQUIRE_MATCHES(run_gpu_hand_color_transfer(texture, state, 1.0f), passes::color_transfer_reference(texture, same_spread, passes::kSigmaFloor, 100.0f),
                     2e-3, 0.0);
  CHECK_THROWS_AS(passes::HandColorTransferPass(test::gpu(), 0.0f), std::invalid_argument);
  CHECK_THROWS_AS(passes::HandColorTransferPass(test::gpu(), std::numeric_limits<float>::quiet_NaN()), std::invalid_argument);
}
