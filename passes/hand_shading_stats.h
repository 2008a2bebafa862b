#pragma once
// Pass: per-workgroup normal equations of appearance adaption's light estimate
// (hand/shading_fit.h): the portrait's brightness over the untouched template's, fitted by the
// shading basis of the mesh's normal, over Eq. 3's pixels.
//   in:  portrait_color rgba32f (I_i, straight alpha), portrait_depth r32f (D_i), mesh_color
//        rgba32f (the template's render), mesh_depth r32f, mesh_mask r32f, mesh_normal rgba32f
//        (unit normal in the site frame, 0 = none) — all of one target view
//   out: partials (ShadingPartial per workgroup of RT_SHADING_STATS_GROUP x
//        RT_SHADING_STATS_PIXELS_PER_THREAD pixels)
// A pixel counts where Eq. 3's statistics count it (passes/hand_color_stats.h) and its normal is
// a unit vector.
#include <functional>

#include "hand/shading_fit.h"
#include "image/host_image.h"
#include "shared/config.h"
#include "shared/hand_shading.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::ShadingPartial;

uint32_t shading_stats_group_count(uint32_t width, uint32_t height);

class HandShadingStatsPass {
 public:
  explicit HandShadingStatsPass(vk::Context& context);
  // `partials` holds at least shading_stats_group_count(width, height) partials.
  void add_to(vk::FrameGraph& graph, vk::Image& portrait_color, vk::Image& portrait_depth, vk::Image& mesh_color,
              vk::Image& mesh_depth, vk::Image& mesh_mask, vk::Image& mesh_normal, vk::Buffer& partials,
              const std::string& pass_name = "hand_shading_stats") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference: the same sums over the whole image, in double precision, with the
// default thresholds (color_stats_params).
hand::ShadingSums shading_stats_reference(const HostImage& portrait_color, const HostImage& portrait_depth,
                                          const HostImage& mesh_color, const HostImage& mesh_depth,
                                          const HostImage& mesh_mask, const HostImage& mesh_normal);

}  // namespace rt::passes
