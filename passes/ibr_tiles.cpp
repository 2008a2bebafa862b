#include "passes/ibr_tiles.h"

#include <stdexcept>
#include <string>

#include "ibr_tiles.comp.h"
#include "shared/config.h"

namespace rt::passes {
namespace {

uint32_t tiles_across(uint32_t pixels, uint32_t tile) { return (pixels + tile - 1) / tile; }

}  // namespace

IbrTiles::IbrTiles(vk::Context& context, uint32_t width, uint32_t height)
    : width_(width),
      height_(height),
      dispatch_(context, {.name = "ibr tile dispatch",
                          .size = 3 * sizeof(uint32_t),
                          .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT}),
      tiles_(context, {.name = "ibr tiles",
                       .size = std::max<VkDeviceSize>(1, VkDeviceSize(tiles_across(width, RT_TILE_X)) *
                                                             tiles_across(height, RT_TILE_Y)) *
                               2 * sizeof(uint32_t)}) {
  if (width == 0 || height == 0) throw std::invalid_argument("ibr tiles: an empty target view");
}

IbrTilesPass::IbrTilesPass(vk::Context& context) : kernel_(context, "ibr_tiles", ibr_tiles_comp_spirv, {}) {}

void IbrTilesPass::add_to(vk::FrameGraph& graph, vk::Image& fused_depth, IbrTiles& tiles, vk::Image& portrait,
                          vk::Image& portrait_depth) const {
  for (const vk::Image* image : {&portrait, &portrait_depth})
    if (image->width() != fused_depth.width() || image->height() != fused_depth.height())
      throw std::invalid_argument("ibr_tiles: '" + image->name() + "' differs in size from the fused depth");
  if (tiles.width() != fused_depth.width() || tiles.height() != fused_depth.height())
    throw std::invalid_argument("ibr_tiles: the tile list is for " + std::to_string(tiles.width()) + "x" +
                                std::to_string(tiles.height()) + ", the fused depth is " +
                                std::to_string(fused_depth.width()) + "x" + std::to_string(fused_depth.height()));
  vk::Buffer& dispatch = tiles.dispatch();
  graph.add_pass({"ibr_tiles_reset",
                  {{&dispatch, vk::access::transfer_write}},
                  [&dispatch](VkCommandBuffer commands) {
                    const uint32_t none_listed[3] = {0, 1, 1};
                    vkCmdUpdateBuffer(commands, dispatch.buffer(), 0, sizeof none_listed, none_listed);
                  }});
  graph.add_compute_pass({
      .name = "ibr_tiles",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth},
                   {"portrait", &portrait},
                   {"portrait_depth", &portrait_depth},
                   {"TileDispatch", &dispatch},
                   {"Tiles", &tiles.tiles()}},
      .threads = {fused_depth.width(), fused_depth.height(), 1},
  });
}

std::vector<std::array<uint32_t, 2>> ibr_tiles_reference(const HostImage& fused_depth) {
  std::vector<std::array<uint32_t, 2>> listed;
  for (uint32_t ty = 0; ty < tiles_across(fused_depth.height, RT_TILE_Y); ++ty)
    for (uint32_t tx = 0; tx < tiles_across(fused_depth.width, RT_TILE_X); ++tx) {
      bool surface = false;
      for (uint32_t y = ty * RT_TILE_Y; y < std::min(fused_depth.height, (ty + 1) * RT_TILE_Y); ++y)
        for (uint32_t x = tx * RT_TILE_X; x < std::min(fused_depth.width, (tx + 1) * RT_TILE_X); ++x)
          surface = surface || fused_depth.at(x, y) > 0.0f;
      if (surface) listed.push_back({tx, ty});
    }
  return listed;
}

}  // namespace rt::passes
