// fma_peak pass (the benchmarks' arithmetic peak): GPU against the C++ reference. The chains may
// run fused or not on either side; the map is contracting (x -> 0.999 x + 0.001), so a lane's
// rounding difference stays below one ulp / (1 - 0.999), about 6e-5 for values up to 1, however
// many iterations; the sum of the 32 lanes may cancel, so the bound is absolute: 32 x 6e-5.
#include <limits>

#include "passes/fma_peak.h"
#include "shared/config.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

std::vector<float> run_gpu_fma_peak(const std::vector<float>& seeds, uint32_t iterations) {
  const passes::FmaPeakPass pass(test::gpu());
  test::PassHarness gpu("fma_peak");
  vk::Buffer& sums = gpu.output_buffer<float>("sums", seeds.size());
  pass.add_to(gpu.graph(), gpu.input_buffer("seeds", seeds), sums, uint32_t(seeds.size()), iterations);
  return gpu.run().values<float>("sums");
}

void require_matches_fma_peak(const std::vector<float>& seeds, uint32_t iterations) {
  const std::vector<float> gpu = run_gpu_fma_peak(seeds, iterations);
  const std::vector<float> reference = passes::fma_peak_reference(seeds, iterations);
  REQUIRE(gpu.size() == reference.size());
  for (size_t i = 0; i < gpu.size(); ++i) {
    INFO("invocation " << i << ", seed " << seeds[i]);
    REQUIRE(std::isfinite(gpu[i]));
    REQUIRE(gpu[i] == Approx(reference[i]).epsilon(0).margin(2e-3));
  }
}

}  // namespace

TEST_CASE("fma_peak on random seeds, odd invocation counts and iteration counts", "[fma_peak][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> seed(-1.5f, 1.5f);
  for (const auto& [invocations, iterations] : std::vector<std::pair<size_t, uint32_t>>{{1, 0}, {63, 1}, {65, 17}, {1001, 300}}) {
    INFO(invocations << " invocations, " << iterations << " iterations");
    std::vector<float> seeds(invocations);
    for (float& s : seeds) s = seed(rng);
    require_matches_fma_peak(seeds, iterations);
  }
}

TEST_CASE("fma_peak hard cases: non-finite and huge seeds give finite sums", "[fma_peak][gpu]") {
  test::NoValidationErrors no_errors;
  const std::vector<float> seeds = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                                    -std::numeric_limits<float>::infinity(), 1e38f, -1e38f, 0.0f};
  require_matches_fma_peak(seeds, 1000);
  CHECK(passes::fma_peak_flops(3, 5) == 3.0 * 5 * RT_FMA_CHAINS * 8);
}
