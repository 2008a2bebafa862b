#pragma once
// Pass: the target view's tiles (RT_TILE_X x RT_TILE_Y pixels) that hold a surface, listed with
// the warp's workgroup counts, and the portrait zeroed (shaders/ibr_tiles.comp), so that
// ibr_warp_blend runs over those tiles alone: on llvmpipe every invocation of a dispatch costs
// the same, whatever its branches skip.
//   in:  fused_depth r32f (0 = nothing)
//   out: IbrTiles (the dispatch's workgroup counts, the tiles), portrait rgba32f and
//        portrait_depth r32f set to 0
#include <array>
#include <cstdint>
#include <vector>

#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

// The listed tiles of a target view of `width` x `height` and the dispatch over them.
class IbrTiles {
 public:
  IbrTiles(vk::Context& context, uint32_t width, uint32_t height);
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  vk::Buffer& dispatch() { return dispatch_; }  // three uints: tiles listed, 1, 1
  vk::Buffer& tiles() { return tiles_; }        // uvec2 per listed tile, in no order

 private:
  uint32_t width_, height_;
  vk::Buffer dispatch_, tiles_;
};

class IbrTilesPass {
 public:
  explicit IbrTilesPass(vk::Context& context);
  // Adds the reset of the tile count and the listing.
  void add_to(vk::FrameGraph& graph, vk::Image& fused_depth, IbrTiles& tiles, vk::Image& portrait,
              vk::Image& portrait_depth) const;

 private:
  vk::ComputeKernel kernel_;
};

// The tiles whose pixels have a fused depth > 0 (NaN is none, +Inf is one), by row then column.
std::vector<std::array<uint32_t, 2>> ibr_tiles_reference(const HostImage& fused_depth);

}  // namespace rt::passes
