// lumi_input: GPU against the C++ reference on random warped views of odd sizes (1x1, a row, a
// column, 641x359, sizes not multiples of the scale), scales 1 to 4, 1 to 6 views, a third of the
// pixels unseen, some NaN features, to 1e-6 absolute + 1e-6 relative (the same sums; only the
// division's rounding may differ); by hand: a block half seen keeps its seen pixels' mean color
// and has coverage 0.5, a block no view sees is all 0, NaN features and colors never reach the
// tensor. No NaN or Inf.
#include <cmath>
#include <limits>
#include <random>

#include "passes/lumi_input.h"
#include "shared/lumi_net.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

constexpr float kNaNLumiInput = std::numeric_limits<float>::quiet_NaN();

passes::LumiInputs run_input(const HostImage& warped, const HostImage& features, uint32_t height, uint32_t views,
                             uint32_t scale) {
  const uint32_t width = warped.width, sw = passes::lumi_small_size(width, scale),
                 sh = passes::lumi_small_size(height, scale);
  const passes::LumiInputPass pass(test::gpu());
  test::PassHarness gpu("lumi_input");
  pass.add_to(gpu.graph(), gpu.input("warped", warped), gpu.input("features", features),
              test::output_tensor(gpu, "inputs", views, RT_LUMI_INPUT_CHANNELS, sw, sh),
              test::output_tensor(gpu, "coverage", views, 1, sw, sh), width, height, views, scale);
  const test::PassOutputs out = gpu.run();
  return {test::tensor_of(out, "inputs", views, RT_LUMI_INPUT_CHANNELS, sw, sh),
          test::tensor_of(out, "coverage", views, 1, sw, sh)};
}

}  // namespace

TEST_CASE("lumi_input on random warped views, odd sizes", "[lumi_input][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const auto& [width, height] : test::odd_sizes())
    for (uint32_t views : {1u, 4u, 6u})
      for (uint32_t scale : {1u, 2u, 3u, 4u}) {
        if (width * height > 10000 && (views != 4 || scale != 2)) continue;  // the large size once
        INFO(width << "x" << height << ", " << views << " views, scale " << scale);
        const HostImage warped = test::random_image(rng, width, height * views, PixelFormat::RGBA32F, -0.2f, 1.2f);
        HostImage features = test::random_image(rng, width, height * views, PixelFormat::RGBA32F);
        for (size_t i = 0; i < features.texels.size(); i += 4) {
          features.texels[i] *= 1.5f;
          features.texels[i + 3] = unit(rng) < 0.67f ? 1.0f : 0.0f;
          if (unit(rng) < 0.02f) features.texels[i + 1] = kNaNLumiInput;
        }
        const passes::LumiInputs gpu = run_input(warped, features, height, views, scale);
        const passes::LumiInputs reference = passes::lumi_input_reference(warped, features, height, views, scale);
        RT_REQUIRE_MATCHES(test::as_image(gpu.inputs), test::as_image(reference.inputs), 1e-6, 1e-6);
        RT_REQUIRE_MATCHES(test::as_image(gpu.coverage), test::as_image(reference.coverage), 0.0, 0.0);
      }
}

TEST_CASE("lumi_input by hand: partly seen blocks, unseen blocks, NaN", "[lumi_input][gpu]") {
  test::NoValidationErrors no_errors;
  // One view, 4x2 at scale 2: block 0 half seen (two pixels of colors 0.2 and 0.6, the other two
  // unseen, one of them with a NaN color), block 1 unseen (one pixel with NaN features).
  HostImage warped(4, 2, PixelFormat::RGBA32F, 0.9f), features(4, 2, PixelFormat::RGBA32F, 0.0f);
  auto seen = [&](uint32_t x, uint32_t y, float color, float angle) {
    for (uint32_t c = 0; c < 3; ++c) warped.at(x, y, c) = color;
    features.at(x, y, 0) = angle;
    features.at(x, y, 1) = 0.1f;
    features.at(x, y, 2) = 1.0f;
    features.at(x, y, 3) = 1.0f;
  };
  seen(0, 0, 0.2f, 0.1f);
  seen(1, 1, 0.6f, 0.3f);
  warped.at(1, 0, 0) = kNaNLumiInput;
  seen(2, 0, 0.5f, kNaNLumiInput);
  const passes::LumiInputs gpu = run_input(warped, features, 2, 1, 2);
  REQUIRE(gpu.inputs.at(0, 0, 0, 0) == Approx(0.4f).epsilon(1e-6));
  REQUIRE(gpu.inputs.at(0, 3, 0, 0) == 0.5f);
  REQUIRE(gpu.inputs.at(0, 4, 0, 0) == Approx(0.2f).epsilon(1e-6));
  REQUIRE(gpu.inputs.at(0, 5, 0, 0) == Approx(0.1f).epsilon(1e-6));
  REQUIRE(gpu.coverage.at(0, 0, 0, 0) == 0.5f);
  for (uint32_t c = 0; c < RT_LUMI_INPUT_CHANNELS; ++c) REQUIRE(gpu.inputs.at(0, c, 1, 0) == 0.0f);
  REQUIRE(gpu.coverage.at(0, 0, 1, 0) == 0.0f);
  RT_REQUIRE_MATCHES(test::as_image(gpu.inputs),
                     test::as_image(passes::lumi_input_reference(warped, features, 2, 1, 2).inputs), 1e-6, 1e-6);
}
