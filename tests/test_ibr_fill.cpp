// ibr_fill: GPU against the C++ reference on random portraits (covered, partly covered, empty and
// NaN alpha; NaN and out-of-range colors) at odd sizes and radii 1, 3 and 8, to 1e-5 (a division
// the GPU may round differently); hard cases with known answers: a one-pixel hole in a uniform
// patch, the inverse-distance weights, a hole open on one side, a hole wider than the radius,
// holes at the image's edge, nothing covered, a tile not listed. No output holds NaN or Inf.
#include <cmath>
#include <limits>
#include <random>

#include "passes/ibr_fill.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"
#include "shared/config.h"

using namespace rt;

namespace {

// The tiles of `listing` (r32f) with a value > 0 are listed by ibr_tiles, whose reset zeroes the
// filled portrait (stale values before); the fill runs over them. By default every tile.
HostImage run_gpu_ibr_fill(const HostImage& portrait, uint32_t radius_px, const HostImage* listing = nullptr) {
  const HostImage everything(portrait.width, portrait.height, PixelFormat::R32F, 1.0f);
  const passes::IbrTilesPass tiling(test::gpu());
  const passes::IbrFillPass pass(test::gpu(), radius_px);
  passes::IbrTiles tiles(test::gpu(), "portrait tiles", portrait.width, portrait.height);
  test::PassHarness gpu("ibr_fill");
  vk::Image& filled = gpu.output("filled", portrait.width, portrait.height, PixelFormat::RGBA32F);
  vk::upload(test::gpu(), filled, HostImage(portrait.width, portrait.height, PixelFormat::RGBA32F, 0.7f));
  tiling.add_to(gpu.graph(), gpu.input("listing", listing ? *listing : everything), tiles, {&filled});
  pass.add_to(gpu.graph(), gpu.input("portrait", portrait), tiles, filled);
  return gpu.run().image("filled");
}

HostImage reference_ibr_fill(const HostImage& portrait, uint32_t radius_px, const HostImage* listing = nullptr) {
  const HostImage everything(portrait.width, portrait.height, PixelFormat::R32F, 1.0f);
  return passes::ibr_fill_reference(portrait, radius_px, passes::ibr_tiles_reference(listing ? *listing : everything));
}

// The portrait's alpha as a listing: its tiles with some coverage (NaN is none).
HostImage alpha_of(const HostImage& portrait) {
  HostImage alpha(portrait.width, portrait.height, PixelFormat::R32F, 0.0f);
  for (uint32_t y = 0; y < portrait.height; ++y)
    for (uint32_t x = 0; x < portrait.width; ++x) alpha.at(x, y) = portrait.at(x, y, 3);
  return alpha;
}

HostImage random_portrait(std::mt19937& rng, uint32_t w, uint32_t h) {
  HostImage portrait = test::random_image(rng, w, h, PixelFormat::RGBA32F, -0.1f, 1.1f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const float u = unit(rng);
      portrait.at(x, y, 3) = u < 0.45f ? 0.0f : u < 0.5f ? 0.3f : u < 0.53f ? nan : u < 0.55f ? 0.5f : 1.0f;
      if (unit(rng) < 0.02f) portrait.at(x, y, 0) = nan;
      if (unit(rng) < 0.01f) portrait.at(x, y, 1) = std::numeric_limits<float>::infinity();
    }
  return portrait;
}

// A portrait of `w` x `h`, uncovered, with a covered patch of one color.
HostImage patch(uint32_t w, uint32_t h, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, float r, float g, float b) {
  HostImage portrait(w, h, PixelFormat::RGBA32F, 0.0f);
  for (uint32_t y = y0; y < y1; ++y)
    for (uint32_t x = x0; x < x1; ++x) {
      portrait.at(x, y, 0) = r, portrait.at(x, y, 1) = g, portrait.at(x, y, 2) = b;
      portrait.at(x, y, 3) = 1.0f;
    }
  return portrait;
}

void uncover(HostImage& portrait, uint32_t x, uint32_t y) {
  for (uint32_t c = 0; c < 4; ++c) portrait.at(x, y, c) = 0.0f;
}

}  // namespace

TEST_CASE("ibr_fill on random portraits, odd sizes, radii 1, 3 and 8", "[ibr_fill][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(83);
  for (uint32_t radius : {1u, 3u, 8u})
    for (const auto& [width, height] : test::odd_sizes()) {
      INFO(width << "x" << height << ", radius " << radius);
      const HostImage portrait = random_portrait(rng, width, height);
      const HostImage expected = reference_ibr_fill(portrait, radius);
      const HostImage gpu = run_gpu_ibr_fill(portrait, radius);
      REQUIRE(test::count_non_finite(gpu) == 0);
      REQUIRE(test::count_non_finite(expected) == 0);
      RT_REQUIRE_MATCHES(gpu, expected, 1e-5, 1e-5);
      // Over the tiles with some coverage alone: the others stay zero.
      HostImage sparse = portrait;
      for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
          if ((x / RT_TILE_X + y / RT_TILE_Y) % 3 == 0) sparse.at(x, y, 3) = 0.0f;
      const HostImage listing = alpha_of(sparse);
      RT_REQUIRE_MATCHES(run_gpu_ibr_fill(sparse, radius, &listing), reference_ibr_fill(sparse, radius, &listing), 1e-5, 1e-5);
    }
}

TEST_CASE("ibr_fill hard cases", "[ibr_fill][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("a one-pixel hole in a uniform patch takes the patch's color and full alpha") {
    HostImage portrait = patch(7, 5, 1, 1, 6, 4, 0.2f, 0.4f, 0.6f);
    uncover(portrait, 3, 2);
    for (const HostImage& out : {run_gpu_ibr_fill(portrait, 2), reference_ibr_fill(portrait, 2)}) {
      CHECK(out.at(3, 2, 0) == Approx(0.2f));
      CHECK(out.at(3, 2, 1) == Approx(0.4f));
      CHECK(out.at(3, 2, 2) == Approx(0.6f));
      CHECK(out.at(3, 2, 3) == 1.0f);
      CHECK(out.at(0, 0, 3) == 0.0f);  // outside the patch: open on two sides
      CHECK(out.at(1, 1, 0) == Approx(0.2f));  // covered pixels as they were
    }
  }
  SECTION("the four nearest covered pixels weigh by the inverse of their distance") {
    // Row 2 of a green patch: (3, 2) and (4, 2) uncovered, blue at (5, 2), red at (1, 2) behind
    // the nearer green (2, 2), so red never counts.
    HostImage portrait = patch(9, 5, 1, 1, 6, 4, 0.0f, 1.0f, 0.0f);
    for (uint32_t x : {3u, 4u}) uncover(portrait, x, 2);
    portrait.at(1, 2, 0) = 1.0f, portrait.at(1, 2, 1) = 0.0f;
    portrait.at(5, 2, 1) = 0.0f, portrait.at(5, 2, 2) = 1.0f;
    // (3, 2)'s nearest: blue (5, 2) at distance 2, green at 1 on the left, above and below.
    for (const HostImage& out : {run_gpu_ibr_fill(portrait, 4), reference_ibr_fill(portrait, 4)}) {
      const float sum = 1.0f + 0.5f + 2.0f;
      CHECK(out.at(3, 2, 0) == Approx(0.0f).margin(1e-6));
      CHECK(out.at(3, 2, 1) == Approx((1.0f + 2.0f) / sum));
      CHECK(out.at(3, 2, 2) == Approx(0.5f / sum));
      // (4, 2): left (3, 2) uncovered, (2, 2) green at 2; right blue at 1; green above and below.
      const float sum4 = 0.5f + 1.0f + 2.0f;
      CHECK(out.at(4, 2, 1) == Approx((0.5f + 2.0f) / sum4));
      CHECK(out.at(4, 2, 2) == Approx(1.0f / sum4));
      CHECK(out.at(4, 2, 3) == 1.0f);
    }
  }
  SECTION("a hole open on one side, one wider than the radius and one at the image's edge stay") {
    HostImage portrait = patch(12, 7, 0, 0, 12, 7, 0.5f, 0.5f, 0.5f);
    for (uint32_t y = 1; y < 7; ++y) uncover(portrait, 2, y);              // a bay open at the bottom edge
    for (uint32_t x = 5; x < 10; ++x) uncover(portrait, x, 3);              // five wide, radius 2
    uncover(portrait, 11, 3);                                               // on the right edge
    uncover(portrait, 7, 5);                                                // enclosed within 1
    for (const HostImage& out : {run_gpu_ibr_fill(portrait, 2), reference_ibr_fill(portrait, 2)}) {
      for (uint32_t y = 1; y < 7; ++y) CHECK(out.at(2, y, 3) == 0.0f);
      CHECK(out.at(7, 3, 3) == 0.0f);  // three from either end of its row, radius 2
      CHECK(out.at(5, 3, 3) == 0.0f);  // one from the row's left end, five from its right
      CHECK(out.at(11, 3, 3) == 0.0f);
      CHECK(out.at(7, 5, 3) == 1.0f);
      CHECK(out.at(7, 5, 0) == Approx(0.5f));
    }
  }
  SECTION("nothing covered: all zeros; one uncovered pixel alone stays uncovered") {
    const HostImage empty(5, 3, PixelFormat::RGBA32F, 0.0f);
    RT_REQUIRE_MATCHES(run_gpu_ibr_fill(empty, 8), empty, 0.0, 0.0);
    const HostImage single(1, 1, PixelFormat::RGBA32F, 0.0f);
    RT_REQUIRE_MATCHES(run_gpu_ibr_fill(single, 1), single, 0.0, 0.0);
  }
  SECTION("a tile not listed is left as the reset left it, holes and all") {
    HostImage portrait = patch(20, 8, 0, 0, 20, 8, 0.5f, 0.5f, 0.5f);
    uncover(portrait, 3, 3);   // in the listed tile
    uncover(portrait, 12, 3);  // in the tile not listed
    HostImage listing(20, 8, PixelFormat::R32F, 0.0f);
    listing.at(0, 0) = 1.0f;
    listing.at(19, 7) = 1.0f;
    for (const HostImage& out : {run_gpu_ibr_fill(portrait, 2, &listing), reference_ibr_fill(portrait, 2, &listing)}) {
      CHECK(out.at(3, 3, 3) == 1.0f);
      CHECK(out.at(3, 3, 0) == Approx(0.5f));
      CHECK(out.at(12, 3, 3) == 0.0f);
      CHECK(out.at(10, 3, 0) == 0.0f);  // covered, but not listed: zero
      CHECK(out.at(17, 3, 3) == 1.0f);
    }
  }
  SECTION("a radius outside 1..64, a mismatched output and a tile list of another size are refused") {
    REQUIRE_THROWS_WITH(passes::IbrFillPass(test::gpu(), 0), Catch::Contains("1..64"));
    REQUIRE_THROWS_WITH(passes::ibr_fill_reference(HostImage(2, 2, PixelFormat::RGBA32F), 65, {}), Catch::Contains("1..64"));
    const passes::IbrFillPass pass(test::gpu(), 2);
    test::PassHarness gpu("ibr_fill");
    passes::IbrTiles tiles(test::gpu(), "portrait tiles", 4, 4);
    vk::Image& portrait = gpu.input("portrait", HostImage(4, 4, PixelFormat::RGBA32F, 0.0f));
    REQUIRE_THROWS_WITH(pass.add_to(gpu.graph(), portrait, tiles, gpu.output("filled", 3, 4, PixelFormat::RGBA32F)),
                        Catch::Contains("not the size"));
    passes::IbrTiles other(test::gpu(), "portrait tiles", 5, 4);
    REQUIRE_THROWS_WITH(pass.add_to(gpu.graph(), portrait, other, gpu.output("filled 2", 4, 4, PixelFormat::RGBA32F)),
                        Catch::Contains("tile list is not"));
  }
}
