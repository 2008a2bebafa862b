// display_view pass: GPU against the C++ reference. The output is 8-bit; the tolerance is one step
// (1/255) for the GPU's float-to-unorm rounding. The texel each window pixel shows is chosen with
// integer arithmetic on both sides, so no pixel may differ by more.
#include <limits>

#include "passes/display_view.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr double kOneStepDisplayView = 1.0 / 255.0 + 1e-6;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

HostImage run_gpu_display_view(const HostImage& source, const passes::DisplayViewMapping& mapping, uint32_t width, uint32_t height) {
  const passes::DisplayViewPass pass(test::gpu());
  test::PassHarness gpu("display_view");
  pass.add_to(gpu.graph(), gpu.input("source", source), gpu.output("view", width, height, PixelFormat::RGBA8),
              [mapping] { return mapping; });
  return gpu.run().image("view");
}

void require_matches(const HostImage& source, const passes::DisplayViewMapping& mapping, uint32_t width, uint32_t height) {
  RT_REQUIRE_MATCHES(run_gpu_display_view(source, mapping, width, height),
                     passes::display_view_reference(source, mapping, width, height), kOneStepDisplayView, 0.0);
}

passes::DisplayViewMapping depth_mapping() {
  passes::DisplayViewMapping mapping;
  mapping.mode = RT_VIEW_DEPTH;
  mapping.low = 0.3f;
  mapping.high = 2.5f;
  return mapping;
}

}  // namespace

TEST_CASE("display_view on random images of odd sizes into windows of other odd sizes", "[display_view][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(11);
  const std::vector<std::pair<uint32_t, uint32_t>> windows = {{1, 1}, {17, 9}, {9, 31}, {64, 36}, {101, 57}};
  size_t case_index = 0;
  for (const auto& [width, height] : test::odd_sizes()) {
    const auto [window_w, window_h] = windows[case_index++ % windows.size()];
    INFO(width << "x" << height << " into " << window_w << "x" << window_h);
    const HostImage color = test::random_image(rng, width, height, PixelFormat::RGBA32F, -0.2f, 1.2f);
    require_matches(color, {}, window_w, window_h);
    const HostImage depth = test::random_image(rng, width, height, PixelFormat::R32F, -0.5f, 3.0f);
    require_matches(depth, depth_mapping(), window_w, window_h);
    passes::DisplayViewMapping channel;
    channel.mode = RT_VIEW_CHANNEL;
    channel.channel = 2;
    channel.low = 0.1f;
    channel.high = 0.7f;
    require_matches(color, channel, window_w, window_h);
    const HostImage color8 = test::random_image(rng, width, height, PixelFormat::RGBA8);
    require_matches(color8, {}, window_w, window_h);
  }
}

TEST_CASE("display_view shows one band of an atlas", "[display_view][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(12);
  const HostImage atlas = test::random_image(rng, 23, 3 * 13, PixelFormat::RGBA32F);
  passes::DisplayViewMapping second_band;
  second_band.band_y0 = 13;
  second_band.band_height = 13;
  require_matches(atlas, second_band, 46, 26);
  // At twice the band's size every source texel covers a 2x2 block: the band itself, nothing else.
  const HostImage view = passes::display_view_reference(atlas, second_band, 46, 26);
  for (uint32_t y = 0; y < 26; ++y)
    for (uint32_t x = 0; x < 46; ++x)
      REQUIRE(std::abs(view.at(x, y, 1) - std::round(std::clamp(atlas.at(x / 2, 13 + y / 2, 1), 0.0f, 1.0f) * 255) / 255) < 1e-6);
  SECTION("a band beyond the atlas shows its last rows, never outside") {
    passes::DisplayViewMapping beyond;
    beyond.band_y0 = 100;
    beyond.band_height = 13;
    require_matches(atlas, beyond, 20, 20);
  }
}

TEST_CASE("display_view hard cases", "[display_view][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("non-finite values show magenta, zero depth dark blue") {
    HostImage depth(5, 1, PixelFormat::R32F);
    depth.texels = {kNaN, kInf, -kInf, 0.0f, 1.0f};
    const HostImage view = run_gpu_display_view(depth, depth_mapping(), 5, 1);
    require_matches(depth, depth_mapping(), 5, 1);
    for (uint32_t x = 0; x < 3; ++x) {
      CHECK(view.at(x, 0, 0) == 1.0f);
      CHECK(view.at(x, 0, 1) == 0.0f);
      CHECK(view.at(x, 0, 2) == 1.0f);
    }
    CHECK(view.at(3, 0, 2) == Approx(64.0 / 255).margin(kOneStepDisplayView));
    CHECK(view.at(4, 0, 0) == Approx(1.0 - (1.0 - 0.3) / 2.2).margin(kOneStepDisplayView));
  }
  SECTION("NaN color, zero alpha") {
    HostImage color = test::filled_image(4, 2, PixelFormat::RGBA32F, 0.0f);
    color.at(1, 0, 1) = kNaN;
    color.at(2, 1, 0) = kInf;
    require_matches(color, {}, 4, 2);
    require_matches(color, {}, 7, 3);
  }
  SECTION("an empty range shows black, never a division by zero") {
    passes::DisplayViewMapping flat;
    flat.mode = RT_VIEW_CHANNEL;
    flat.low = flat.high = 0.5f;
    const HostImage source = test::filled_image(3, 3, PixelFormat::R32F, 0.7f);
    require_matches(source, flat, 3, 3);
  }
  SECTION("a one-pixel source fills the window, a window of one pixel shows one texel") {
    std::mt19937 rng(13);
    require_matches(test::random_image(rng, 1, 1, PixelFormat::RGBA32F), {}, 9, 5);
    require_matches(test::random_image(rng, 31, 17, PixelFormat::RGBA32F), {}, 1, 1);
  }
  SECTION("a very wide source into a tall window keeps its aspect: bars above and below") {
    std::mt19937 rng(14);
    const HostImage wide = test::random_image(rng, 40, 2, PixelFormat::RGBA32F);
    const HostImage view = run_gpu_display_view(wide, {}, 20, 20);
    require_matches(wide, {}, 20, 20);
    CHECK(view.at(10, 0, 0) == 0.0f);
    CHECK(view.at(10, 19, 0) == 0.0f);
    CHECK(view.at(10, 0, 3) == 1.0f);
  }
}
