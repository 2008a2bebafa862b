// ibr_fuse: GPU against the C++ reference from given fusion buffers (random ones of odd sizes,
// both fusions), and the hard cases: filling closes a one-pixel crack but not the outside of a
// silhouette nor a gap across a depth edge; a buffer of the wrong size is refused. Tolerance:
// 1e-6 m absolute + 1e-5 relative.
#include <bit>
#include <span>

#include "passes/ibr_fuse.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

HostImage run_gpu_ibr_fuse(const std::vector<uint32_t>& fusion, uint32_t width, uint32_t height,
                  const passes::FuseSettings& settings = {}) {
  const passes::IbrFusePass pass(test::gpu(), settings);
  test::PassHarness gpu("ibr_fuse");
  pass.add_to(gpu.graph(), gpu.buffer(passes::fusion_buffer_desc(width, height), std::as_bytes(std::span(fusion))),
              gpu.output("fused depth", width, height, PixelFormat::R32F));
  return gpu.run().image("fused depth");
}

}  // namespace

TEST_CASE("ibr_fuse from a given fusion buffer", "[ibr_fuse][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(22);
  for (const auto& [width, height] : test::odd_sizes()) {
    for (auto mode : {passes::DepthFusion::Min, passes::DepthFusion::Average}) {
      INFO(width << "x" << height);
      const size_t n = size_t(width) * height;
      std::vector<uint32_t> fusion(3 * n, 0u);
      std::uniform_real_distribution<float> depth(0.5f, 1.5f), unit(0.0f, 1.0f);
      for (size_t i = 0; i < n; ++i) {
        if (unit(rng) < 0.3f) {
          fusion[i] = RT_IBR_EMPTY_DEPTH_BITS;
          continue;
        }
        const float z = unit(rng) < 0.5f ? 0.8f + 0.01f * unit(rng) : depth(rng);  // a flat patch and clutter
        fusion[i] = std::bit_cast<uint32_t>(z);
        fusion[2 * n + i] = 1 + uint32_t(unit(rng) * 3);
        fusion[n + i] = uint32_t(z * 1e5f) * fusion[2 * n + i];
      }
      passes::FuseSettings settings;
      settings.fusion = mode;
      RT_REQUIRE_MATCHES(run_gpu_ibr_fuse(fusion, width, height, settings),
                         passes::ibr_fuse_reference(fusion, width, height, settings), 1e-6, 1e-5);
    }
  }
}

TEST_CASE("ibr_fuse hard cases", "[ibr_fuse][gpu]") {
  test::NoValidationErrors no_errors;
  const size_t n = 45 * 27;

  SECTION("filling closes a one-pixel crack but not the outside of an edge, nor across a depth edge") {
    std::vector<uint32_t> fusion(3 * n, 0u);
    std::fill_n(fusion.begin(), n, RT_IBR_EMPTY_DEPTH_BITS);
    for (uint32_t y = 5; y < 20; ++y)
      for (uint32_t x = 5; x < 30; ++x)
        if (x != 15) fusion[y * 45 + x] = std::bit_cast<uint32_t>(x < 15 ? 1.0f : 1.01f);  // crack at x = 15
    for (uint32_t y = 5; y < 20; ++y) fusion[y * 45 + 31] = std::bit_cast<uint32_t>(1.0f);
    for (uint32_t y = 5; y < 20; ++y) fusion[y * 45 + 33] = std::bit_cast<uint32_t>(1.5f);  // gap at 32 across an edge
    const HostImage filled = passes::ibr_fuse_reference(fusion, 45, 27);
    REQUIRE(filled.at(15, 10) == Approx(1.005f).epsilon(1e-3));  // crack filled with the mean
    REQUIRE(filled.at(4, 10) == 0.0f);                            // outside the silhouette
    REQUIRE(filled.at(32, 10) == 0.0f);                           // between 1.0 and 1.5 m: an edge
    RT_REQUIRE_MATCHES(run_gpu_ibr_fuse(fusion, 45, 27), filled, 1e-6, 1e-5);
  }
  SECTION("a fusion buffer of the wrong size is refused") {
    vk::Buffer small(test::gpu(), passes::fusion_buffer_desc(4, 4));
    vk::Image fused(test::gpu(), {"fused depth", 45, 27, PixelFormat::R32F});
    vk::FrameGraph graph(test::gpu(), "refused");
    REQUIRE_THROWS_WITH(passes::IbrFusePass(test::gpu()).add_to(graph, small, fused), Catch::Contains("does not match"));
  }
}
