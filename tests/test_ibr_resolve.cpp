// ibr_resolve: GPU against the C++ reference on random fine portraits (binary and partial
// alpha, holes) at odd sizes and factors 2..4, to 1e-5 (the same sums in another order); hard
// cases: nothing covered (alpha 0, color 0, depth 0), NaN and Inf in the input (never in the
// output), a half-covered pixel (alpha 0.5, the covered samples' color), and the image-based
// model with a supersampled portrait (partial alpha on its silhouette, no NaN).
#include <cmath>
#include <limits>

#include "config/assets.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/site_simulator.h"
#include "passes/ibr_resolve.h"
#include "sim/scene.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

passes::Portrait run_gpu_ibr_resolve(const HostImage& fine_portrait, const HostImage& fine_depth, uint32_t factor) {
  const passes::IbrResolvePass pass(test::gpu(), factor);
  test::PassHarness gpu("ibr_resolve");
  const uint32_t w = fine_portrait.width / factor, h = fine_portrait.height / factor;
  pass.add_to(gpu.graph(), gpu.input("fine portrait", fine_portrait), gpu.input("fine depth", fine_depth),
              gpu.output("portrait", w, h, PixelFormat::RGBA32F), gpu.output("portrait depth", w, h, PixelFormat::R32F));
  const test::PassOutputs out = gpu.run();
  return {out.image("portrait"), out.image("portrait depth")};
}

// A fine portrait as the blend writes it: alpha 0 or 1 (some 0.5 to exercise partial input),
// straight color, depth where covered.
std::pair<HostImage, HostImage> random_fine(std::mt19937& rng, uint32_t w, uint32_t h) {
  HostImage color = test::random_image(rng, w, h, PixelFormat::RGBA32F);
  HostImage depth = test::random_image(rng, w, h, PixelFormat::R32F, 0.5f, 1.5f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const float u = unit(rng);
      color.at(x, y, 3) = u < 0.4f ? 0.0f : u < 0.5f ? 0.5f : 1.0f;
      if (color.at(x, y, 3) == 0.0f) depth.at(x, y) = 0.0f;
    }
  return {color, depth};
}

}  // namespace

TEST_CASE("ibr_resolve on random fine portraits, odd sizes, factors 2 to 4", "[ibr_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(61);
  for (uint32_t factor : {2u, 3u, 4u})
    for (const auto& [width, height] : test::odd_sizes()) {
      INFO(width << "x" << height << " x" << factor);
      const auto [color, depth] = random_fine(rng, width * factor, height * factor);
      const passes::Portrait gpu = run_gpu_ibr_resolve(color, depth, factor);
      const passes::Portrait reference = passes::ibr_resolve_reference(color, depth, factor);
      REQUIRE(test::count_non_finite(gpu.color) == 0);
      RT_REQUIRE_MATCHES(gpu.color, reference.color, 1e-5, 1e-5);
      RT_REQUIRE_MATCHES(gpu.depth, reference.depth, 0.0, 0.0);
    }
}

TEST_CASE("ibr_resolve hard cases", "[ibr_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("nothing covered: alpha 0, color 0, depth 0") {
    const HostImage color(6, 4, PixelFormat::RGBA32F, 0.0f), depth(6, 4, PixelFormat::R32F, 0.0f);
    const passes::Portrait gpu = run_gpu_ibr_resolve(color, depth, 2);
    RT_REQUIRE_MATCHES(gpu.color, HostImage(3, 2, PixelFormat::RGBA32F, 0.0f), 0.0, 0.0);
    RT_REQUIRE_MATCHES(gpu.depth, HostImage(3, 2, PixelFormat::R32F, 0.0f), 0.0, 0.0);
  }
  SECTION("a half-covered pixel: alpha 0.5, the covered samples' color, the nearest depth off-centre") {
    HostImage color(2, 2, PixelFormat::RGBA32F, 0.0f), depth(2, 2, PixelFormat::R32F, 0.0f);
    for (uint32_t y = 0; y < 2; ++y) {  // left column covered: color (0.2, 0.4, 0.6)
      color.at(0, y, 0) = 0.2f, color.at(0, y, 1) = 0.4f, color.at(0, y, 2) = 0.6f, color.at(0, y, 3) = 1.0f;
      depth.at(0, y) = 1.0f + 0.1f * float(y);
    }
    for (const passes::Portrait& out : {run_gpu_ibr_resolve(color, depth, 2), passes::ibr_resolve_reference(color, depth, 2)}) {
      CHECK(out.color.at(0, 0, 0) == Approx(0.2f));
      CHECK(out.color.at(0, 0, 2) == Approx(0.6f));
      CHECK(out.color.at(0, 0, 3) == Approx(0.5f));
      CHECK(out.depth.at(0, 0) == Approx(1.0f));  // the centre sample (1, 1) is empty
    }
  }
  SECTION("NaN and Inf in the input never reach the output") {
    std::mt19937 rng(62);
    auto [color, depth] = random_fine(rng, 9, 6);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    color.at(0, 0, 3) = nan;
    color.at(1, 0, 0) = nan;
    color.at(3, 1, 3) = inf;
    color.at(4, 2, 1) = -inf;
    depth.at(2, 2) = nan;
    depth.at(5, 3) = inf;
    const passes::Portrait gpu = run_gpu_ibr_resolve(color, depth, 3);
    REQUIRE(test::count_non_finite(gpu.color) == 0);
    REQUIRE(test::count_non_finite(gpu.depth) == 0);
    RT_REQUIRE_MATCHES(gpu.color, passes::ibr_resolve_reference(color, depth, 3).color, 1e-5, 1e-5);
  }
  SECTION("refusals") {
    vk::Image fine(test::gpu(), {"fine", 10, 10, PixelFormat::RGBA32F});
    vk::Image fine_z(test::gpu(), {"fine z", 10, 10, PixelFormat::R32F});
    vk::Image portrait(test::gpu(), {"portrait", 4, 4, PixelFormat::RGBA32F});
    vk::Image depth(test::gpu(), {"portrait depth", 4, 4, PixelFormat::R32F});
    vk::FrameGraph graph(test::gpu(), "refused");
    REQUIRE_THROWS_WITH(passes::IbrResolvePass(test::gpu(), 2).add_to(graph, fine, fine_z, portrait, depth),
                        Catch::Contains("not 2 times"));
    REQUIRE_THROWS_WITH(passes::IbrResolvePass(test::gpu(), 5), Catch::Contains("2..4"));
  }
}

TEST_CASE("the image-based model with a supersampled portrait: partial alpha on the silhouette", "[ibr_resolve][gpu]") {
  test::NoValidationErrors no_errors;
  sim::Scene scene = sim::load_scene(rt::config::assets_dir() / "scenes" / "wave.json");
  scene.frame_count = 1;
  scene.resolution_scale = 0.25;
  pipeline::SiteSimulator simulator(test::gpu(), scene, Site::A, 47, 27);
  const sim::RgbdFrame frame = *simulator.next_frame();
  std::vector<passes::IbrCameraModel> cameras;
  for (size_t k = 0; k < simulator.renderer().camera_count(); ++k)
    cameras.push_back({simulator.renderer().camera(k).color, simulator.renderer().camera(k).depth});
  pipeline::IbrSettings settings;
  settings.width = 47;
  settings.height = 27;
  settings.supersample = 3;
  pipeline::IbrRenderer renderer(test::gpu(), cameras, settings);
  const std::vector<size_t> selection{0, 1, 3, 4};
  renderer.render(frame.cameras, selection, *simulator.renderer().target_view());
  const HostImage portrait = vk::download(test::gpu(), renderer.portrait());
  REQUIRE(portrait.width == 47);
  REQUIRE(test::count_non_finite(portrait) == 0);
  REQUIRE(test::count_non_finite(vk::download(test::gpu(), renderer.portrait_depth())) == 0);
  size_t full = 0, partial = 0;
  for (uint32_t y = 0; y < 27; ++y)
    for (uint32_t x = 0; x < 47; ++x) {
      const float alpha = portrait.at(x, y, 3);
      full += alpha == 1.0f;
      partial += alpha > 0.0f && alpha < 1.0f;
    }
  CHECK(full > 20);
  CHECK(partial > 5);
  pipeline::IbrSettings too_fine = settings;
  too_fine.supersample = 5;
  REQUIRE_THROWS_WITH(pipeline::IbrRenderer(test::gpu(), cameras, too_fine), Catch::Contains("supersample must be 1..4"));
}
