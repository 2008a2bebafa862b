// composite pass: GPU against the C++ reference. The output is 8-bit; the tolerance is one
// step (1/255) for the GPU's float-to-unorm rounding.
#include <limits>

#include "passes/composite.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr double kOneStepComposite = 1.0 / 255.0 + 1e-6;

HostImage run_gpu_composite(const HostImage& fused, const HostImage& background) {
  const passes::CompositePass pass(test::gpu());
  test::PassHarness gpu("composite");
  pass.add_to(gpu.graph(), gpu.input("fused", fused), gpu.input("background", background),
              gpu.output("display", fused.width, fused.height, PixelFormat::RGBA8));
  return gpu.run().image("display");
}

// Random premultiplied layers: color never above alpha.
HostImage random_premultiplied(std::mt19937& rng, uint32_t w, uint32_t h) {
  HostImage image = test::random_image(rng, w, h, PixelFormat::RGBA32F);
  for (size_t i = 0; i < image.texels.size(); i += 4)
    for (int c = 0; c < 3; ++c) image.texels[i + c] *= image.texels[i + 3];
  return image;
}

}  // namespace

TEST_CASE("composite on random layers of odd sizes", "[composite][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(7);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const HostImage fused = random_premultiplied(rng, width, height);
    const HostImage background = test::random_image(rng, width, height, PixelFormat::RGBA32F);
    RT_REQUIRE_MATCHES(run_gpu_composite(fused, background), passes::composite_reference(fused, background), kOneStepComposite, 0.0);
  }
}

TEST_CASE("composite hard cases", "[composite][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(8);
  const uint32_t w = 9, h = 1;
  const HostImage background = test::random_image(rng, w, h, PixelFormat::RGBA32F);
  HostImage opaque_background = background;
  for (size_t i = 3; i < opaque_background.texels.size(); i += 4) opaque_background.texels[i] = 1.0f;

  SECTION("alpha 0 everywhere shows the background") {
    const HostImage fused = test::filled_image(w, h, PixelFormat::RGBA32F, 0.0f);
    RT_REQUIRE_MATCHES(run_gpu_composite(fused, background), opaque_background, kOneStepComposite, 0.0);
  }
  SECTION("alpha 1 everywhere shows the layer") {
    HostImage fused = random_premultiplied(rng, w, h);
    for (size_t i = 3; i < fused.texels.size(); i += 4) fused.texels[i] = 1.0f;
    RT_REQUIRE_MATCHES(run_gpu_composite(fused, background), passes::composite_reference(fused, background), kOneStepComposite, 0.0);
    HostImage expected = fused;
    RT_REQUIRE_MATCHES(run_gpu_composite(fused, background), expected, kOneStepComposite, 0.0);
  }
  SECTION("non-finite and out-of-range values stay in range") {
    HostImage fused = random_premultiplied(rng, w, h);
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(), -1.0f, 5.0f};
    for (size_t i = 0; i < fused.texels.size(); i += 2) fused.texels[i] = bad[i % 5];
    HostImage bad_background = background;
    for (size_t i = 1; i < bad_background.texels.size(); i += 3) bad_background.texels[i] = bad[i % 5];
    RT_REQUIRE_MATCHES(run_gpu_composite(fused, bad_background), passes::composite_reference(fused, bad_background), kOneStepComposite, 0.0);
  }
}
