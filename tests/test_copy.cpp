// copy pass (the benchmarks' roofline): the copy must be exact.
#include "passes/copy.h"
#include "support/gpu_test.h"
#include "vulkan/frame_graph.h"

using namespace rt;

TEST_CASE("copy reproduces random images of odd sizes exactly", "[copy][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const passes::CopyPass pass(context);
  std::mt19937 rng(9);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const HostImage source_pixels = test::random_image(rng, width, height, PixelFormat::RGBA32F, -1e6f, 1e6f);
    vk::Image source(context, {"copy source", width, height, PixelFormat::RGBA32F});
    vk::Image destination(context, {"copy destination", width, height, PixelFormat::RGBA32F});
    vk::upload(context, source, source_pixels);
    vk::FrameGraph graph(context, "test copy");
    pass.add_to(graph, source, destination);
    graph.run();
    RT_REQUIRE_MATCHES(vk::download(context, destination), source_pixels, 0.0, 0.0);
  }
}
