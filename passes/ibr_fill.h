#pragma once
// Pass: the portrait's small enclosed holes filled (shaders/ibr_fill.comp says which pixels and
// how), so that a crack between splats or a spot no camera saw does not show the background
// through the remote user. It runs over listed tiles alone (passes/ibr_tiles.h), whose reset
// zeroed the filled portrait.
//   in:  portrait rgba32f (straight color, alpha), IbrTiles of its size
//   out: filled portrait rgba32f, the same size, in the listed tiles (the rest stays as the reset
//        left it): covered pixels (alpha >= 0.5) as they were, an
//        uncovered pixel with a covered one within the radius in all four directions of its row
//        and column the inverse-distance mean of those four's colors with alpha 1, any other as
//        it was; colors in [0, 1] and alpha in [0, 1] (NaN read as 0)
#include <cstdint>

#include <vector>

#include "image/host_image.h"
#include "passes/ibr_tiles.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class IbrFillPass {
 public:
  // radius_px: how far (pixels) a hole's sides may be, 1..64.
  IbrFillPass(vk::Context& context, uint32_t radius_px);
  void add_to(vk::FrameGraph& graph, vk::Image& portrait, IbrTiles& tiles, vk::Image& filled) const;
  uint32_t radius_px() const { return radius_px_; }

 private:
  uint32_t radius_px_;
  vk::ComputeKernel kernel_;
};

// The plain C++ reference: the listed tiles filled, the rest 0.
HostImage ibr_fill_reference(const HostImage& portrait, uint32_t radius_px, const std::vector<TileIndex>& tiles);

}  // namespace rt::passes
