// copy pass (the benchmarks' roofline): the copy must be exact.
#include "passes/copy.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

TEST_CASE("copy reproduces random images of odd sizes exactly", "[copy][gpu]") {
  test::NoValidationErrors no_errors;
  const passes::CopyPass pass(test::gpu());
  std::mt19937 rng(9);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const HostImage source = test::random_image(rng, width, height, PixelFormat::RGBA32F, -1e6f, 1e6f);
    test::PassHarness gpu("copy");
    pass.add_to(gpu.graph(), gpu.input("copy source", source),
                gpu.output("copy destination", width, height, PixelFormat::RGBA32F));
    RT_REQUIRE_MATCHES(gpu.run().image("copy destination"), source, 0.0, 0.0);
  }
}
