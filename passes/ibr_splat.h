#pragma once
// Pass: depth reprojection into the target view with the min-filter (shaders/ibr_splat.comp).
//   in:  points rgba32f atlas (ibr_foreground), the camera table
//   out: the fusion buffer (3 uints per target pixel: nearest depth bits, sum and count of the
//        depths within average_tolerance_m of it), cleared first by a fill.
// Min fusion runs one dispatch; average fusion (the baseline) adds a second that accumulates.
#include <cstdint>
#include <vector>

#include "passes/common/ibr_scene.h"
#include "passes/ibr_tiles.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

enum class DepthFusion { Min, Average };

struct SplatSettings {
  DepthFusion fusion = DepthFusion::Min;
  float footprint_scale = 1.0f;   // splat side over a depth pixel's projected size
  float max_footprint_px = 6.0f;
  // Average fusion: the depths within this of the nearest agree with it and join its mean. 1.5 cm
  // holds one surface's samples from all views (their spread on the default stand is a few
  // millimetres) and no surface behind it; eval ibr measured it best on wave and clap (10 cm,
  // the plain mean over most of a hand-over-body edge, blurs the edges as the paper says).
  float average_tolerance_m = 0.015f;
  // A splat is the piece of its surface around the point, spanned by the neighbouring points within
  // this depth of it: four quarters, each on the plane through the point and the two neighbours
  // bounding it (a missing neighbour mirrors the opposite one); without a neighbour on both axes
  // it is a flat square. Its depth stays within about this of the point's.
  float plane_tolerance_m = 0.03f;
  // A surface splat's sides without a neighbour on its surface (outlines, depth edges) pull in by
  // this much of a depth pixel (squares keep their size). The min-filter keeps the union of the
  // views' splats, so each outline otherwise grows by the largest of the views' half-pixel
  // errors, about 0.5 - 1 / (k + 1) depth pixels for k views that see it (0.36 for six). Off by
  // default: 0.3 gains with six views and a supersampled portrait, and loses with four views or
  // one sample per target pixel, where an uncovered pixel costs its whole color (README).
  float edge_inset = 0.0f;
};

// A fusion buffer for a target of this size: usable as storage and as a fill destination.
vk::BufferDesc fusion_buffer_desc(uint32_t target_width, uint32_t target_height);

class IbrSplatPass {
 public:
  IbrSplatPass(vk::Context& context, const SplatSettings& settings = {});
  // Runs over the tiles of `points` that point_tiles lists (ibr_foreground's).
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& points, IbrTiles& point_tiles,
              vk::Buffer& fusion, uint32_t view_count) const;
  const SplatSettings& settings() const { return settings_; }

 private:
  SplatSettings settings_;
  vk::ComputeKernel nearest_;
  vk::ComputeKernel average_;
};

// The plain C++ reference: the fusion buffer's contents.
std::vector<uint32_t> ibr_splat_reference(const IbrSceneTable& table, const HostImage& points,
                                          const SplatSettings& settings = {});

}  // namespace rt::passes
