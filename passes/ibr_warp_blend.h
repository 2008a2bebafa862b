#pragma once
// Pass: warping and unstructured lumigraph blending in one (shaders/ibr_warp_blend.comp), the
// image-based model's path when it blends by lumigraph weights: every view is sampled and
// blended in registers, so no per-view atlas is written and read back. Its result is that of
// ibr_warp followed by ibr_blend (a learned blending still takes that split path).
//   in:  fused_depth r32f, color rgba8 atlas (views in bands), points rgba32f atlas (each view's
//        own depth in w), the camera table, the tiles with a surface (ibr_tiles, which also
//        zeroed the portrait: this pass writes those tiles alone)
//   out: portrait rgba32f (straight color, alpha 1 where a view sees the surface, else 0),
//        portrait_depth r32f (metres, 0 = nothing)
#include "passes/common/ibr_scene.h"
#include "passes/ibr_blend.h"
#include "passes/ibr_tiles.h"
#include "passes/ibr_warp.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class IbrWarpBlendPass {
 public:
  // `view_count` views (1 to RT_IBR_MAX_VIEWS) in the atlases' bands, built into the kernel.
  IbrWarpBlendPass(vk::Context& context, uint32_t view_count, const WarpSettings& warp = {},
                   const BlendSettings& blend = {});
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& color,
              vk::Image& points, IbrTiles& tiles, vk::Image& portrait, vk::Image& portrait_depth) const;

 private:
  uint32_t view_count_;
  vk::ComputeKernel kernel_;
};

// ibr_blend_reference of ibr_warp_reference: the split path's references, composed.
Portrait ibr_warp_blend_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& color,
                                  const HostImage& points, const WarpSettings& warp = {},
                                  const BlendSettings& blend = {});

}  // namespace rt::passes
