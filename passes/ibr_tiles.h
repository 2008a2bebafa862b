#pragma once
// Pass: the target view's tiles (RT_TILE_X x RT_TILE_Y pixels) that hold a surface, listed with
// the warp's workgroup counts (shaders/ibr_tiles.comp), after a transfer that clears the images
// that the passes over the list write, so that ibr_warp_blend (and ibr_fill) run over those tiles
// alone: on llvmpipe every invocation of a dispatch costs the same, whatever its branches skip.
//   in:  depth r32f (0 = nothing): the fused depth, or a portrait's depth
//   out: IbrTiles (the dispatch's workgroup counts, the tiles), the zeroed images (e.g. the
//        portrait rgba32f and its depth r32f) set to 0
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

// The listed tiles of an image of `width` x `height` pixels per layer (a view's band of an
// atlas), `layers` of them, and the dispatch over them. Each entry is a uvec4: the tile's column,
// row and layer, and 0. `name` names both buffers (captures and validation messages show it).
class IbrTiles {
 public:
  IbrTiles(vk::Context& context, const std::string& name, uint32_t width, uint32_t height, uint32_t layers = 1);
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  uint32_t layers() const { return layers_; }
  // Whether these are the tiles of `atlas`, its rows in `layers()` bands of `height()` each.
  bool lists_bands_of(const vk::Image& atlas) const {
    return atlas.width() == width_ && atlas.height() == height_ * layers_;
  }
  vk::Buffer& dispatch() { return dispatch_; }  // three uints: tiles listed, 1, 1
  vk::Buffer& tiles() { return tiles_; }        // per listed tile, in no order

 private:
  uint32_t width_, height_, layers_;
  vk::Buffer dispatch_, tiles_;
};

// Adds a pass `name` that sets the count of listed tiles to 0, before the pass that lists them.
void add_tile_reset(vk::FrameGraph& graph, const std::string& name, IbrTiles& tiles);

class IbrTilesPass {
 public:
  // `name` names the listing pass, and with "_reset" its reset (a graph with two lists names them apart).
  explicit IbrTilesPass(vk::Context& context, std::string name = "ibr_tiles");
  // Adds the reset of the tile count with the clear of `zeroed` (images of the depth's size that
  // passes over the listed tiles alone write, such as the portrait and its depth), and the listing.
  void add_to(vk::FrameGraph& graph, vk::Image& depth, IbrTiles& tiles, const std::vector<vk::Image*>& zeroed) const;

 private:
  std::string name_;
  vk::ComputeKernel kernel_;
};

using TileIndex = std::array<uint32_t, 3>;  // column, row, layer

// The tiles with a pixel whose channel `channel` is > 0 (NaN is not, +Inf is), the image's rows
// in `layers` bands of equal height; by layer, row, then column. With the defaults, the tiles
// ibr_tiles lists from a fused depth.
std::vector<TileIndex> ibr_tiles_reference(const HostImage& image, uint32_t layers = 1, uint32_t channel = 0);

}  // namespace rt::passes
