#pragma once
// Pass: background removal for every view of the image-based model (shaders/ibr_foreground.comp).
//   in:  depth_mm r16ui atlas (views in bands, 0 = invalid), depth_rays rgba32f atlas (ibr_scene.h),
//        the camera table
//   out: points rgba32f atlas: site-frame xyz and camera z of each foreground pixel, 0 elsewhere;
//        the tiles of it that hold a point (IbrTiles, one layer per view), for ibr_splat.
// Foreground = inside the user's volume and at least `min_support` of 8 neighbours also inside
// it within `edge_tolerance_m` in depth (cleans flying pixels and fringes at the silhouette).
#include <Eigen/Core>

#include "passes/common/ibr_scene.h"
#include "passes/ibr_tiles.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct ForegroundSettings {
  // The user's volume in the site frame: in front of the screen, around the seat.
  Eigen::Vector3f volume_min{-1.0f, -1.2f, 0.0f};
  Eigen::Vector3f volume_max{1.0f, 1.0f, 1.3f};
  int min_support = 4;
  float edge_tolerance_m = 0.04f;
};

class IbrForegroundPass {
 public:
  IbrForegroundPass(vk::Context& context, const ForegroundSettings& settings = {});
  // Adds the reset of point_tiles' count and the pass.
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& depth_mm, vk::Image& depth_rays,
              vk::Image& points, IbrTiles& point_tiles, uint32_t view_count) const;

 private:
  ForegroundSettings settings_;
  vk::ComputeKernel kernel_;
};

// The plain C++ reference; `depth_mm` and `depth_rays` are atlases of table.camera_count bands.
HostImage ibr_foreground_reference(const IbrSceneTable& table, const HostImage& depth_mm, const HostImage& depth_rays,
                                   const ForegroundSettings& settings = {});

}  // namespace rt::passes
