// hand_resolve: GPU against the C++ reference on random layers of odd sizes (masks with zeros,
// partial coverage and ones; depths with zeros), factors 1 to 4, tolerance 1e-6 absolute + 1e-6
// relative (the same sums in the same order). Hard cases: no coverage at all, a half-covered
// pixel, NaN and Inf in every input, a depth of zero under coverage, and refused factors and sizes.
// No NaN or Inf in any output.
#include <cmath>
#include <limits>
#include <random>

#include "passes/hand_resolve.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

passes::HandLayers run_gpu_hand_resolve(const HostImage& color, const HostImage& mask, const HostImage& depth, uint32_t factor) {
  const passes::HandResolvePass pass(test::gpu(), factor);
  test::PassHarness gpu("hand_resolve");
  const uint32_t w = color.width / factor, h = color.height / factor;
  pass.add_to(gpu.graph(), {&gpu.input("fine color", color), &gpu.input("fine mask", mask), &gpu.input("fine depth", depth)},
              {&gpu.output("color", w, h, PixelFormat::RGBA32F), &gpu.output("mask", w, h, PixelFormat::R32F),
               &gpu.output("depth", w, h, PixelFormat::R32F)});
  const test::PassOutputs out = gpu.run();
  return {out.image("color"), out.image("mask"), out.image("depth")};
}

void require_matches_hand_resolve(const HostImage& color, const HostImage& mask, const HostImage& depth, uint32_t factor) {
  const passes::HandLayers gpu = run_gpu_hand_resolve(color, mask, depth, factor);
  const passes::HandLayers reference = passes::hand_resolve_reference(color, mask, depth, factor);
  RT_REQUIRE_MATCHES(gpu.color, reference.color, 1e-6, 1e-6);
  RT_REQUIRE_MATCHES(gpu.mask, reference.mask, 1e-6, 1e-6);
  RT_REQUIRE_MATCHES(gpu.depth_m, reference.depth_m, 0.0, 0.0);
}

}  // namespace

TEST_CASE("hand_resolve on random layers of odd sizes", "[hand_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(83);
  std::uniform_int_distribution<int> kind(0, 3);
  for (uint32_t factor : {1u, 2u, 3u, 4u})
    for (const auto& [width, height] : test::odd_sizes()) {
      if (width * height * factor * factor > 400'000) continue;
      INFO(width << "x" << height << " x" << factor);
      const uint32_t fw = width * factor, fh = height * factor;
      const HostImage color = test::random_image(rng, fw, fh, PixelFormat::RGBA32F);
      HostImage mask = test::random_image(rng, fw, fh, PixelFormat::R32F);
      HostImage depth = test::random_image(rng, fw, fh, PixelFormat::R32F, 0.2f, 3.0f);
      // Most of a hand layer is either off the hand or on it; a few samples are partial.
      for (uint32_t y = 0; y < fh; ++y)
        for (uint32_t x = 0; x < fw; ++x) {
          const int k = kind(rng);
          if (k == 0) mask.at(x, y) = 0.0f, depth.at(x, y) = 0.0f;
          if (k == 1) mask.at(x, y) = 1.0f;
        }
      require_matches_hand_resolve(color, mask, depth, factor);
    }
}

TEST_CASE("hand_resolve hard cases", "[hand_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  SECTION("no coverage: color, mask and depth all zero") {
    const passes::HandLayers gpu = run_gpu_hand_resolve(HostImage(6, 4, PixelFormat::RGBA32F, 0.7f), HostImage(6, 4, PixelFormat::R32F, 0.0f),
                                           HostImage(6, 4, PixelFormat::R32F, 1.0f), 2);
    RT_REQUIRE_MATCHES(gpu.color, HostImage(3, 2, PixelFormat::RGBA32F, 0.0f), 0.0, 0.0);
    RT_REQUIRE_MATCHES(gpu.mask, HostImage(3, 2, PixelFormat::R32F, 0.0f), 0.0, 0.0);
    RT_REQUIRE_MATCHES(gpu.depth_m, HostImage(3, 2, PixelFormat::R32F, 0.0f), 0.0, 0.0);
  }
  SECTION("an edge across a pixel: the covered fraction, the covered samples' color, the nearest depth") {
    HostImage color(2, 2, PixelFormat::RGBA32F, 0.0f), mask(2, 2, PixelFormat::R32F, 0.0f), depth(2, 2, PixelFormat::R32F, 0.0f);
    for (uint32_t y = 0; y < 2; ++y) {
      mask.at(0, y) = 1.0f;
      color.at(0, y, 0) = 0.5f + 0.25f * float(y);
      depth.at(0, y) = 1.0f + float(y);
    }
    const passes::HandLayers gpu = run_gpu_hand_resolve(color, mask, depth, 2);
    REQUIRE(gpu.mask.at(0, 0) == Approx(0.5f));
    REQUIRE(gpu.color.at(0, 0, 0) == Approx(0.625f));
    REQUIRE(gpu.color.at(0, 0, 3) == 1.0f);
    REQUIRE(gpu.depth_m.at(0, 0) == 1.0f);
  }
  SECTION("NaN and Inf in color, mask and depth never reach the outputs") {
    std::mt19937 rng(5);
    HostImage color = test::random_image(rng, 9, 6, PixelFormat::RGBA32F);
    HostImage mask = test::random_image(rng, 9, 6, PixelFormat::R32F);
    HostImage depth = test::random_image(rng, 9, 6, PixelFormat::R32F, 0.2f, 3.0f);
    const float bad[] = {nan, inf, -inf};
    for (uint32_t i = 0; i < 9 * 6; i += 2) {
      const uint32_t x = i % 9, y = i / 9;
      color.at(x, y, i % 3) = bad[i % 3];
      if (i % 4 == 0) mask.at(x, y) = bad[(i / 4) % 3];
      if (i % 6 == 0) depth.at(x, y) = bad[(i / 6) % 3];
      if (i % 10 == 0) depth.at(x, y) = 0.0f;  // covered, but with no depth
    }
    require_matches_hand_resolve(color, mask, depth, 3);
  }
  SECTION("factors outside 1 to 4 and mismatched sizes are refused") {
    REQUIRE_THROWS_WITH(passes::HandResolvePass(test::gpu(), 0), Catch::Contains("1 to 4"));
    REQUIRE_THROWS_WITH(passes::HandResolvePass(test::gpu(), 5), Catch::Contains("1 to 4"));
    vk::Context& context = test::gpu();
    vk::Image fine(context, {"fine", 8, 8, PixelFormat::RGBA32F}), fine_r(context, {"fine r", 8, 8, PixelFormat::R32F});
    vk::Image coarse(context, {"coarse", 3, 3, PixelFormat::RGBA32F}), coarse_r(context, {"coarse r", 3, 3, PixelFormat::R32F});
    const passes::HandResolvePass pass(context, 2);
    vk::FrameGraph graph(context, "refusal");
    REQUIRE_THROWS_WITH(pass.add_to(graph, {&fine, &fine_r, &fine_r}, {&coarse, &coarse_r, &coarse_r}), Catch::Contains("is not 2 x 3x3"));
  }
}
