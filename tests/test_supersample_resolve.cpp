// supersample_resolve: GPU against the C++ reference. Color is 8-bit: one step (1/255) of
// tolerance for the GPU's rounding of the mean; depth and part are copied exactly.
#include "passes/supersample_resolve.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

struct Resolved {
  HostImage color, depth_m, part;
};

Resolved run_gpu_supersample_resolve(const HostImage& color, const HostImage& depth, const HostImage& part, uint32_t factor) {
  const passes::SupersampleResolvePass pass(test::gpu(), factor);
  test::PassHarness gpu("supersample_resolve");
  const uint32_t w = color.width / factor, h = color.height / factor;
  pass.add_to(gpu.graph(),
              {&gpu.input("fine color", color), &gpu.input("fine depth", depth), &gpu.input("fine part", part)},
              {&gpu.output("color", w, h, PixelFormat::RGBA8), &gpu.output("depth", w, h, PixelFormat::R32F),
               &gpu.output("part", w, h, PixelFormat::R32F)});
  const test::PassOutputs out = gpu.run();
  return {out.image("color"), out.image("depth"), out.image("part")};
}

}  // namespace

TEST_CASE("supersample_resolve on random images of odd sizes", "[supersample_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(51);
  for (uint32_t factor : {1u, 3u, 5u})
    for (const auto& [width, height] : test::odd_sizes()) {
      if (width * height * factor * factor > 400'000) continue;
      INFO(width << "x" << height << " x" << factor);
      const uint32_t fw = width * factor, fh = height * factor;
      const HostImage color = test::random_image(rng, fw, fh, PixelFormat::RGBA8);
      const HostImage depth = test::random_image(rng, fw, fh, PixelFormat::R32F, 0.0f, 3.0f);
      const HostImage part = test::random_image(rng, fw, fh, PixelFormat::R32F, 0.0f, 2.0f);
      const Resolved gpu = run_gpu_supersample_resolve(color, depth, part, factor);
      RT_REQUIRE_MATCHES(gpu.color, passes::supersample_resolve_reference(color, factor), 1.0 / 255 + 1e-6, 0.0);
      RT_REQUIRE_MATCHES(gpu.depth_m, passes::supersample_resolve_reference(depth, factor), 0.0, 0.0);
      RT_REQUIRE_MATCHES(gpu.part, passes::supersample_resolve_reference(part, factor), 0.0, 0.0);
    }
}

TEST_CASE("supersample_resolve hard cases", "[supersample_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("an edge half across a pixel resolves to the half-way color") {
    HostImage color(3, 3, PixelFormat::RGBA8, 0.0f);
    for (uint32_t y = 0; y < 3; ++y)
      for (uint32_t c = 0; c < 4; ++c) color.at(0, y, c) = 1.0f;  // one column of three lit
    const Resolved gpu = run_gpu_supersample_resolve(color, HostImage(3, 3, PixelFormat::R32F, 1.0f), HostImage(3, 3, PixelFormat::R32F, 2.0f), 3);
    REQUIRE(gpu.color.at(0, 0, 0) == Approx(1.0f / 3.0f).margin(1.0 / 255));
    REQUIRE(gpu.part.at(0, 0) == 2.0f);
  }
  SECTION("even factors and mismatched sizes are refused") {
    REQUIRE_THROWS_WITH(passes::SupersampleResolvePass(test::gpu(), 2), Catch::Contains("odd"));
    vk::Context& context = test::gpu();
    vk::Image fine(context, {"fine", 9, 9, PixelFormat::RGBA8}), fine_r(context, {"fine r", 9, 9, PixelFormat::R32F});
    vk::Image out(context, {"out", 4, 3, PixelFormat::RGBA8}), out_r(context, {"out r", 4, 3, PixelFormat::R32F});
    vk::FrameGraph graph(context, "refused");
    REQUIRE_THROWS_WITH(passes::SupersampleResolvePass(context, 3).add_to(graph, {&fine, &fine_r, &fine_r}, {&out, &out_r, &out_r}),
                        Catch::Contains("is not 3 x 4x3"));
  }
}
