// ibr_tiles: GPU against the C++ reference on random fused depths of odd sizes (the tiles listed,
// in any order, exactly once each; the dispatch's counts; the portrait zeroed everywhere) and
// the hard cases: no surface at all, NaN, infinite and negative depths, a surface only in the
// partial tiles at the edges, a surface everywhere. Exact: the listing is integer work.
#include <algorithm>
#include <cstring>
#include <limits>

#include "passes/ibr_tiles.h"
#include "shared/config.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

using Tile = passes::TileIndex;

struct Listed {
  std::array<uint32_t, 3> dispatch{};
  std::vector<Tile> tiles;  // sorted by row, then column
  HostImage portrait, portrait_depth;
};

Listed run_gpu_ibr_tiles(const HostImage& fused) {
  const passes::IbrTilesPass pass(test::gpu());
  passes::IbrTiles tiles(test::gpu(), "surface tiles", fused.width, fused.height);
  test::PassHarness gpu("ibr_tiles");
  // Stale values from an earlier frame: the pass resets the count and overwrites the portrait.
  vk::Image& portrait = gpu.output("portrait", fused.width, fused.height, PixelFormat::RGBA32F);
  vk::Image& portrait_depth = gpu.output("portrait depth", fused.width, fused.height, PixelFormat::R32F);
  vk::upload(test::gpu(), portrait, HostImage(fused.width, fused.height, PixelFormat::RGBA32F, 0.5f));
  vk::upload(test::gpu(), portrait_depth, HostImage(fused.width, fused.height, PixelFormat::R32F, 0.5f));
  pass.add_to(gpu.graph(), gpu.input("fused depth", fused), tiles, {&portrait, &portrait_depth});
  const std::array<uint32_t, 3> stale_dispatch{7, 7, 7};
  vk::upload(test::gpu(), tiles.dispatch(), std::as_bytes(std::span(stale_dispatch)));
  const test::PassOutputs out = gpu.run();
  Listed listed{{}, {}, out.image("portrait"), out.image("portrait depth")};
  const std::vector<std::byte> dispatch = vk::download(test::gpu(), tiles.dispatch());
  std::memcpy(listed.dispatch.data(), dispatch.data(), sizeof listed.dispatch);
  listed.tiles = test::listed_tiles(tiles);
  return listed;
}

void require_matches_reference(const HostImage& fused) {
  const Listed gpu = run_gpu_ibr_tiles(fused);
  const std::vector<Tile> reference = passes::ibr_tiles_reference(fused);
  REQUIRE(gpu.dispatch == std::array<uint32_t, 3>{uint32_t(reference.size()), 1, 1});
  REQUIRE(gpu.tiles == reference);
  RT_REQUIRE_MOSTLY_MATCHES(gpu.portrait, HostImage(fused.width, fused.height, PixelFormat::RGBA32F, 0.0f), 0.0, 0.0, 0);
  RT_REQUIRE_MOSTLY_MATCHES(gpu.portrait_depth, HostImage(fused.width, fused.height, PixelFormat::R32F, 0.0f), 0.0, 0.0,
                            0);
}

}  // namespace

TEST_CASE("ibr_tiles on random fused depths, odd sizes", "[ibr_tiles][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(41);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    // Sparse surfaces, so that many tiles hold none.
    HostImage fused(width, height, PixelFormat::R32F, 0.0f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (float& z : fused.texels) z = unit(rng) < 0.02f ? 0.5f + unit(rng) : 0.0f;
    require_matches_reference(fused);
  }
}

TEST_CASE("ibr_tiles hard cases", "[ibr_tiles][gpu]") {
  test::NoValidationErrors no_errors;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  SECTION("no surface: nothing listed, the portrait zeroed") {
    const HostImage fused(37, 21, PixelFormat::R32F, 0.0f);
    REQUIRE(passes::ibr_tiles_reference(fused).empty());
    require_matches_reference(fused);
  }
  SECTION("NaN and negative depths are no surface, an infinite one is") {
    HostImage fused(37, 21, PixelFormat::R32F, 0.0f);
    fused.texels[fused.index(3, 3)] = nan;
    fused.texels[fused.index(12, 3)] = -1.0f;
    fused.texels[fused.index(20, 12)] = inf;
    REQUIRE(passes::ibr_tiles_reference(fused) == std::vector<Tile>{{20 / RT_TILE_X, 12 / RT_TILE_Y, 0}});
    require_matches_reference(fused);
  }
  SECTION("a surface only in the partial tiles of the last column and row") {
    HostImage fused(37, 21, PixelFormat::R32F, 0.0f);
    fused.texels[fused.index(36, 0)] = 1.0f;
    fused.texels[fused.index(0, 20)] = 1.0f;
    REQUIRE(passes::ibr_tiles_reference(fused).size() == 2);
    require_matches_reference(fused);
  }
  SECTION("a surface everywhere: every tile once") {
    const HostImage fused(37, 21, PixelFormat::R32F, 1.0f);
    REQUIRE(passes::ibr_tiles_reference(fused).size() == size_t((37 + RT_TILE_X - 1) / RT_TILE_X) *
                                                              ((21 + RT_TILE_Y - 1) / RT_TILE_Y));
    require_matches_reference(fused);
  }
  SECTION("a tile list of another size is refused") {
    const passes::IbrTilesPass pass(test::gpu());
    passes::IbrTiles tiles(test::gpu(), "surface tiles", 36, 21);
    test::PassHarness gpu("ibr_tiles");
    REQUIRE_THROWS_WITH(pass.add_to(gpu.graph(), gpu.scratch("fused depth", 37, 21, PixelFormat::R32F), tiles,
                                    {&gpu.scratch("portrait", 37, 21, PixelFormat::RGBA32F),
                                     &gpu.scratch("portrait depth", 37, 21, PixelFormat::R32F)}),
                        Catch::Contains("the tile list is for 36x21"));
    passes::IbrTiles fitting(test::gpu(), "surface tiles", 37, 21);
    test::PassHarness other("ibr_tiles");
    REQUIRE_THROWS_WITH(pass.add_to(other.graph(), other.scratch("fused depth", 37, 21, PixelFormat::R32F), fitting,
                                    {&other.scratch("portrait", 37, 20, PixelFormat::RGBA32F)}),
                        Catch::Contains("'portrait' differs in size from 'fused depth'"));
  }
}
