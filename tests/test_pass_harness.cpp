// The pass tests' support: comparisons refuse images of different shapes, saying both; the
// harness returns outputs by name, refuses unknown names and reused ones, reads back buffers.
#include "passes/copy.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

TEST_CASE("comparisons refuse images whose sizes or channel counts differ", "[support]") {
  const HostImage image(7, 5, PixelFormat::RGBA32F, 0.5f);
  const HostImage taller(7, 6, PixelFormat::RGBA32F, 0.5f), one_channel(7, 5, PixelFormat::R32F, 0.5f);
  for (const HostImage* other : {&taller, &one_channel}) {
    CHECK_THROWS_WITH(test::compare(*other, image, 0.0, 0.0),
                      Catch::Contains("compare") && Catch::Contains("7x5 with 4 channels"));
    CHECK_THROWS_WITH(test::compare_pixels(*other, image, 0.0, 0.0),
                      Catch::Contains("compare_pixels") && Catch::Contains("7x5 with 4 channels"));
  }
  CHECK_THROWS_WITH(test::compare(taller, image, 0.0, 0.0), Catch::Contains("7x6"));
  CHECK_THROWS_WITH(test::compare(one_channel, image, 0.0, 0.0), Catch::Contains("1 channel"));
  HostImage short_of_texels = image;
  short_of_texels.texels.pop_back();
  CHECK_THROWS_WITH(test::compare_pixels(short_of_texels, image, 0.0, 0.0), Catch::Contains("values"));
  CHECK(test::compare(image, image, 0.0, 0.0).mismatches == 0);
  CHECK(test::compare_pixels(image, image, 0.0, 0.0).mismatched_pixels == 0);
}

TEST_CASE("the pass harness runs a pass and returns its outputs by name", "[support][gpu]") {
  test::NoValidationErrors no_errors;
  const passes::CopyPass copy(test::gpu());
  std::mt19937 rng(3);
  const HostImage source = test::random_image(rng, 9, 4, PixelFormat::RGBA32F);
  test::PassHarness gpu("harness");
  vk::Image& in = gpu.input("in", source);
  CHECK_THROWS_WITH(gpu.output("in", 9, 4, PixelFormat::RGBA32F), Catch::Contains("already has a resource 'in'"));
  vk::Image& unread = gpu.scratch("unread", 9, 4, PixelFormat::RGBA32F);
  copy.add_to(gpu.graph(), in, unread, "first");
  copy.add_to(gpu.graph(), unread, gpu.output("out", 9, 4, PixelFormat::RGBA32F), "second");
  const std::vector<uint32_t> values = {1, 2, 3};
  gpu.input_buffer("kept", values, true);
  gpu.output_buffer<uint32_t>("nothing", 0);
  const test::PassOutputs out = gpu.run();
  RT_REQUIRE_MATCHES(out.image("out"), source, 0.0, 0.0);
  CHECK(out.values<uint32_t>("kept") == values);
  CHECK(out.values<uint32_t>("nothing").empty());
  CHECK_THROWS_WITH(out.image("unread"), Catch::Contains("no image output 'unread'") && Catch::Contains("'out'"));
  CHECK_THROWS_WITH(out.value<uint32_t>("kept"), Catch::Contains("3 values, not one"));
  CHECK_THROWS_WITH(out.values<uint64_t>("kept"), Catch::Contains("not a whole number"));
  CHECK_THROWS_WITH(gpu.graph(), Catch::Contains("already run"));
}
