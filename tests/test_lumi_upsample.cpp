// lumi_upsample: GPU against the C++ reference on random small tensors for odd targets (1x1, a
// row, a column, sizes that are not multiples of the scale), scales 1, 2, 3 and 4, 1 and 7
// planes, to 1e-6 absolute + 1e-6 relative; by hand: the half-pixel centres (PyTorch's
// interpolate(align_corners=False)) on a ramp, a constant stays constant, scale 1 is a copy.
// No NaN or Inf.
#include <random>

#include "passes/lumi_input.h"
#include "passes/lumi_upsample.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

passes::LumiTensor run_upsample(const passes::LumiTensor& small, uint32_t width, uint32_t height, uint32_t scale) {
  const passes::LumiUpsamplePass pass(test::gpu());
  test::PassHarness gpu("lumi_upsample");
  pass.add_to(gpu.graph(), test::input_tensor(gpu, "small", small),
              test::output_tensor(gpu, "full", 1, small.channels, width, height), width, height, small.channels, scale);
  return test::tensor_of(gpu.run(), "full", 1, small.channels, width, height);
}

}  // namespace

TEST_CASE("lumi_upsample on random tensors, odd sizes", "[lumi_upsample][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(41);
  for (const auto& [width, height] : test::lumi_sizes())
    for (uint32_t scale : {1u, 2u, 3u, 4u})
      for (uint32_t planes : {1u, 7u}) {
        INFO(width << "x" << height << ", scale " << scale << ", " << planes << " planes");
        const passes::LumiTensor small = passes::random_lumi_tensor(
            rng, 1, planes, passes::lumi_small_size(width, scale), passes::lumi_small_size(height, scale), 0.0f, 1.0f);
        RT_REQUIRE_MATCHES(test::as_image(run_upsample(small, width, height, scale)),
                           test::as_image(passes::lumi_upsample_reference(small, width, height, scale)), 1e-6, 1e-6);
      }
}

TEST_CASE("lumi_upsample by hand: half-pixel centres, constants, scale 1", "[lumi_upsample][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("a ramp 0, 1, 2 at scale 2: PyTorch's values, the edges clamped") {
    passes::LumiTensor small(1, 1, 3, 1);
    for (uint32_t x = 0; x < 3; ++x) small.at(0, 0, x, 0) = float(x);
    const passes::LumiTensor full = run_upsample(small, 6, 1, 2);
    const float expected[6] = {0.0f, 0.25f, 0.75f, 1.25f, 1.75f, 2.0f};
    for (uint32_t x = 0; x < 6; ++x) REQUIRE(full.at(0, 0, x, 0) == Approx(expected[x]).margin(1e-6));
  }
  SECTION("a constant stays the constant, cropped to an odd target") {
    const passes::LumiTensor full = run_upsample(passes::LumiTensor(1, 2, 3, 2, 0.625f), 5, 3, 2);
    RT_REQUIRE_MATCHES(test::as_image(full), test::as_image(passes::LumiTensor(1, 2, 5, 3, 0.625f)), 1e-7, 0.0);
  }
  SECTION("scale 1 copies") {
    std::mt19937 rng(3);
    const passes::LumiTensor small = passes::random_lumi_tensor(rng, 1, 3, 9, 7);
    RT_REQUIRE_MATCHES(test::as_image(run_upsample(small, 9, 7, 1)), test::as_image(small), 0.0, 0.0);
  }
}
