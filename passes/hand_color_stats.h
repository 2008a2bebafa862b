#pragma once
// Pass: per-workgroup color statistics for appearance adaption (paper Eq. 3).
//   in:  portrait_color rgba32f (I_i, straight alpha), portrait_depth r32f (D_i), mesh_color
//        rgba32f (I_g), mesh_depth r32f (D_g), mesh_mask r32f — all of one target view
//   out: partials (ColorStatsPartial per workgroup of RT_COLOR_STATS_GROUP x
//        RT_COLOR_STATS_PIXELS_PER_THREAD pixels)
// A pixel counts when the mesh covers it, the portrait has alpha > 0.5, both depths are valid
// and agree within the tolerance, and neither color is black or saturated in any channel.
#include <Eigen/Core>
#include <functional>

#include "image/host_image.h"
#include "shared/config.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::ColorStatsParams;
using shader_abi::ColorStatsPartial;

ColorStatsParams color_stats_params(uint32_t width, uint32_t height);  // the defaults below
inline constexpr float kBlackLevel = 1.0f / 255.0f;
inline constexpr float kSaturatedLevel = 254.0f / 255.0f;
uint32_t color_stats_group_count(uint32_t width, uint32_t height);

class HandColorStatsPass {
 public:
  explicit HandColorStatsPass(vk::Context& context);
  // `partials` holds at least color_stats_group_count(width, height) partials.
  void add_to(vk::FrameGraph& graph, vk::Image& portrait_color, vk::Image& portrait_depth, vk::Image& mesh_color,
              vk::Image& mesh_depth, vk::Image& mesh_mask, vk::Buffer& partials,
              const std::string& pass_name = "hand_color_stats") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference: the same sums over the whole image, in double precision.
struct ColorSums {
  double count = 0;
  Eigen::Vector3d image_sum = Eigen::Vector3d::Zero(), image_sum_sq = Eigen::Vector3d::Zero();
  Eigen::Vector3d mesh_sum = Eigen::Vector3d::Zero(), mesh_sum_sq = Eigen::Vector3d::Zero();
};
// Whether the pixel counts for Eq. 3 (the rule above), as common/hand_fit_pixel.glsl decides it.
bool hand_fit_pixel_reference(const HostImage& portrait_color, const HostImage& portrait_depth, const HostImage& mesh_color,
                              const HostImage& mesh_depth, const HostImage& mesh_mask, uint32_t x, uint32_t y,
                              const ColorStatsParams& params);
ColorSums color_stats_reference(const HostImage& portrait_color, const HostImage& portrait_depth, const HostImage& mesh_color,
                                const HostImage& mesh_depth, const HostImage& mesh_mask, const ColorStatsParams& params);

}  // namespace rt::passes
