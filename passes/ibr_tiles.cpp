#include "passes/ibr_tiles.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "ibr_tiles.comp.h"
#include "shared/config.h"

namespace rt::passes {
namespace {

uint32_t tiles_across(uint32_t pixels, uint32_t tile) { return (pixels + tile - 1) / tile; }

void record_tile_reset(VkCommandBuffer commands, vk::Buffer& dispatch) {
  const uint32_t none_listed[3] = {0, 1, 1};
  vkCmdUpdateBuffer(commands, dispatch.buffer(), 0, sizeof none_listed, none_listed);
}

}  // namespace

IbrTiles::IbrTiles(vk::Context& context, const std::string& name, uint32_t width, uint32_t height, uint32_t layers)
    : width_(width),
      height_(height),
      layers_(layers),
      dispatch_(context, {.name = name + " dispatch",
                          .size = 3 * sizeof(uint32_t),
                          .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT}),
      tiles_(context, {.name = name,
                       .size = std::max<VkDeviceSize>(1, VkDeviceSize(tiles_across(width, RT_TILE_X)) *
                                                             tiles_across(height, RT_TILE_Y) * layers) *
                               4 * sizeof(uint32_t)}) {
  if (width == 0 || height == 0 || layers == 0) throw std::invalid_argument("ibr tiles: an empty image");
}

void add_tile_reset(vk::FrameGraph& graph, const std::string& name, IbrTiles& tiles) {
  vk::Buffer& dispatch = tiles.dispatch();
  graph.add_pass({name, {{&dispatch, vk::access::transfer_write}},
                  [&dispatch](VkCommandBuffer commands) { record_tile_reset(commands, dispatch); }});
}

IbrTilesPass::IbrTilesPass(vk::Context& context, std::string name)
    : name_(std::move(name)), kernel_(context, "ibr_tiles", ibr_tiles_comp_spirv, {}) {}

void IbrTilesPass::add_to(vk::FrameGraph& graph, vk::Image& depth, IbrTiles& tiles,
                          const std::vector<vk::Image*>& zeroed) const {
  for (const vk::Image* image : zeroed)
    if (image->width() != depth.width() || image->height() != depth.height())
      throw std::invalid_argument("ibr_tiles: '" + image->name() + "' differs in size from '" + depth.name() + "'");
  if (!tiles.lists_bands_of(depth))
    throw std::invalid_argument("ibr_tiles: the tile list is for " + std::to_string(tiles.width()) + "x" +
                                std::to_string(tiles.height()) + ", '" + depth.name() + "' is " +
                                std::to_string(depth.width()) + "x" + std::to_string(depth.height()));
  if (tiles.layers() != 1) throw std::invalid_argument("ibr_tiles: a tile list of one layer is needed");
  // The count reset and the images zeroed by transfers: a clear is a memset, where a kernel's
  // stores would cost llvmpipe a pass of its own.
  vk::Buffer& dispatch = tiles.dispatch();
  std::vector<vk::ResourceUse> uses{{&dispatch, vk::access::transfer_write}};
  for (vk::Image* image : zeroed) uses.push_back({image, vk::access::transfer_write});
  graph.add_pass({name_ + "_reset", std::move(uses), [&dispatch, zeroed](VkCommandBuffer commands) {
                    record_tile_reset(commands, dispatch);
                    const VkClearColorValue zero{};
                    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                    for (vk::Image* image : zeroed)
                      vkCmdClearColorImage(commands, image->image(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1,
                                           &range);
                  }});
  graph.add_compute_pass({
      .name = name_,
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &depth}, {"TileDispatch", &dispatch}, {"Tiles", &tiles.tiles()}},
      .threads = {depth.width(), depth.height(), 1},
  });
}

std::vector<TileIndex> ibr_tiles_reference(const HostImage& image, uint32_t layers, uint32_t channel) {
  if (layers == 0 || image.height % layers != 0 || channel >= image.channels())
    throw std::invalid_argument("ibr tiles: the image does not hold " + std::to_string(layers) + " bands or channel " +
                                std::to_string(channel));
  const uint32_t height = image.height / layers;
  std::vector<TileIndex> listed;
  for (uint32_t layer = 0; layer < layers; ++layer)
    for (uint32_t ty = 0; ty < tiles_across(height, RT_TILE_Y); ++ty)
      for (uint32_t tx = 0; tx < tiles_across(image.width, RT_TILE_X); ++tx) {
        bool found = false;
        for (uint32_t y = ty * RT_TILE_Y; y < std::min(height, (ty + 1) * RT_TILE_Y); ++y)
          for (uint32_t x = tx * RT_TILE_X; x < std::min(image.width, (tx + 1) * RT_TILE_X); ++x)
            found = found || image.at(x, y + layer * height, channel) > 0.0f;
        if (found) listed.push_back({tx, ty, layer});
      }
  return listed;
}

}  // namespace rt::passes
