#include "passes/ibr_warp_blend.h"

#include <stdexcept>
#include <string>

#include "ibr_warp_blend.comp.h"

namespace rt::passes {

namespace {

uint32_t checked_view_count(uint32_t view_count) {
  if (view_count == 0 || view_count > RT_IBR_MAX_VIEWS)
    throw std::invalid_argument("ibr_warp_blend: 1 to " + std::to_string(RT_IBR_MAX_VIEWS) + " views");
  return view_count;
}

}  // namespace

IbrWarpBlendPass::IbrWarpBlendPass(vk::Context& context, uint32_t view_count, const WarpSettings& warp,
                                   const BlendSettings& blend)
    : view_count_(checked_view_count(view_count)),
      kernel_(context, "ibr_warp_blend", ibr_warp_blend_comp_spirv,
              {{"visibility_tolerance_m", checked_warp_settings(warp).visibility.metres},
               {"visibility_tolerance_rel", warp.visibility.relative},
               {"feather_px", warp.feather_px},
               {"best_views", int32_t(checked_blend_settings(blend).best_views)},
               {"resolution_weight", blend.resolution_weight},
               {"view_count", int32_t(view_count)}}) {}

void IbrWarpBlendPass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& color,
                              vk::Image& points, IbrTiles& tiles, vk::Image& portrait,
                              vk::Image& portrait_depth) const {
  if (color.height() % view_count_ != 0 || points.height() % view_count_ != 0)
    throw std::invalid_argument("ibr_warp_blend: the color and points atlases must hold " + std::to_string(view_count_) +
                                " bands");
  for (const vk::Image* image : {&portrait, &portrait_depth})
    if (image->width() != fused_depth.width() || image->height() != fused_depth.height())
      throw std::invalid_argument("ibr_warp_blend: '" + image->name() + "' differs in size from the fused depth");
  if (tiles.layers() != 1 || !tiles.lists_bands_of(fused_depth))
    throw std::invalid_argument("ibr_warp_blend: the tile list differs in size from the fused depth");
  graph.add_compute_pass({
      .name = "ibr_warp_blend",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth}, {"color", &color}, {"points", &points}, {"portrait", &portrait},
                   {"portrait_depth", &portrait_depth}, {"IbrSceneTable", &scene.buffer()}, {"Tiles", &tiles.tiles()}},
      .indirect = &tiles.dispatch(),
  });
}

Portrait ibr_warp_blend_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& color,
                                  const HostImage& points, const WarpSettings& warp, const BlendSettings& blend) {
  const WarpedViews warped = ibr_warp_reference(table, fused_depth, color, points, warp);
  return ibr_blend_reference(fused_depth, warped.warped, warped.features, table.camera_count, blend);
}

}  // namespace rt::passes
