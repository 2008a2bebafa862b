// lumi_pool: GPU against the C++ reference on random tensors of odd sizes, channel counts that
// are not multiples of 4, 1 to 6 views with random coverage (about a third of the views blind at
// each pixel), exactly (the same sums in the same order). By hand: the mean and max over the
// seeing views only, a single seeing view, none (pooled 0), and a blind view still getting the
// pool. No NaN or Inf.
#include <random>

#include "passes/lumi_pool.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

passes::LumiTensor run_pool(const passes::LumiTensor& source, const passes::LumiTensor& coverage) {
  const passes::LumiPoolPass pass(test::gpu(), source.channels);
  test::PassHarness gpu("lumi_pool");
  pass.add_to(gpu.graph(), "lumi_pool", test::input_tensor(gpu, "source", source),
              test::input_tensor(gpu, "coverage", coverage),
              test::output_tensor(gpu, "result", source.views, 3 * source.channels, source.width, source.height),
              source.width, source.height, source.views);
  return test::tensor_of(gpu.run(), "result", source.views, 3 * source.channels, source.width, source.height);
}

passes::LumiTensor random_coverage(std::mt19937& rng, uint32_t views, uint32_t width, uint32_t height) {
  passes::LumiTensor coverage = passes::random_lumi_tensor(rng, views, 1, width, height, 0.0f, 1.0f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (float& c : coverage.values)
    if (unit(rng) < 0.35f) c = 0.0f;
  return coverage;
}

}  // namespace

TEST_CASE("lumi_pool on random tensors, odd sizes", "[lumi_pool][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(17);
  for (const auto& [width, height] : test::lumi_sizes())
    for (uint32_t channels : {1u, 5u, 16u})
      for (uint32_t views : {1u, 2u, 6u}) {
        INFO(width << "x" << height << ", " << channels << " channels, " << views << " views");
        const passes::LumiTensor source = passes::random_lumi_tensor(rng, views, channels, width, height);
        const passes::LumiTensor coverage = random_coverage(rng, views, width, height);
        RT_REQUIRE_MATCHES(test::as_image(run_pool(source, coverage)),
                           test::as_image(passes::lumi_pool_reference(source, coverage)), 0.0, 0.0);
      }
}

TEST_CASE("lumi_pool by hand: seeing views only, one view, none", "[lumi_pool][gpu]") {
  test::NoValidationErrors no_errors;
  // One channel, three views, three pixels: all see; only view 1 sees; none sees.
  passes::LumiTensor source(3, 1, 3, 1), coverage(3, 1, 3, 1);
  const float values[3] = {-2.0f, 4.0f, 1.0f};
  for (uint32_t v = 0; v < 3; ++v)
    for (uint32_t x = 0; x < 3; ++x) source.at(v, 0, x, 0) = values[v];
  for (uint32_t v = 0; v < 3; ++v) coverage.at(v, 0, 0, 0) = 0.5f;
  coverage.at(1, 0, 1, 0) = 1.0f;
  const passes::LumiTensor gpu = run_pool(source, coverage);
  for (uint32_t v = 0; v < 3; ++v) {
    REQUIRE(gpu.at(v, 0, 0, 0) == values[v]);  // own
    REQUIRE(gpu.at(v, 1, 0, 0) == 1.0f);       // mean of -2, 4, 1
    REQUIRE(gpu.at(v, 2, 0, 0) == 4.0f);       // max
    REQUIRE(gpu.at(v, 1, 1, 0) == 4.0f);       // one seeing view: its value, for the blind ones too
    REQUIRE(gpu.at(v, 2, 1, 0) == 4.0f);
    REQUIRE(gpu.at(v, 1, 2, 0) == 0.0f);       // none seeing: 0, not the blind views' values
    REQUIRE(gpu.at(v, 2, 2, 0) == 0.0f);
  }
}
