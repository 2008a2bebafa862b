#include "passes/hand_shading_stats.h"

#include <cmath>

#include "passes/hand_color_stats.h"
#include "hand_shading_stats.comp.h"

namespace rt::passes {

uint32_t shading_stats_group_count(uint32_t width, uint32_t height) {
  const uint32_t per_group = RT_SHADING_STATS_GROUP * RT_SHADING_STATS_PIXELS_PER_THREAD;
  return (width * height + per_group - 1) / per_group;
}

HandShadingStatsPass::HandShadingStatsPass(vk::Context& context)
    : kernel_(context, "hand_shading_stats", hand_shading_stats_comp_spirv) {}

void HandShadingStatsPass::add_to(vk::FrameGraph& graph, vk::Image& portrait_color, vk::Image& portrait_depth,
                                  vk::Image& mesh_color, vk::Image& mesh_depth, vk::Image& mesh_mask,
                                  vk::Image& mesh_normal, vk::Buffer& partials, const std::string& pass_name) const {
  const uint32_t width = mesh_color.width(), height = mesh_color.height();
  for (vk::Image* image : {&portrait_color, &portrait_depth, &mesh_depth, &mesh_mask, &mesh_normal})
    if (image->width() != width || image->height() != height)
      throw std::invalid_argument("pass '" + pass_name + "': image '" + image->name() + "' differs in size from '" +
                                  mesh_color.name() + "'");
  if (partials.size() < shading_stats_group_count(width, height) * sizeof(ShadingPartial))
    throw std::invalid_argument("pass '" + pass_name + "': buffer '" + partials.name() + "' is too small");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"portrait_color", &portrait_color}, {"portrait_depth", &portrait_depth}, {"mesh_color", &mesh_color},
                   {"mesh_depth", &mesh_depth}, {"mesh_mask", &mesh_mask}, {"mesh_normal", &mesh_normal},
                   {"Partials", &partials}},
      .threads = {shading_stats_group_count(width, height) * RT_SHADING_STATS_GROUP, 1, 1},
      .push_constants = vk::push_constants_from<ColorStatsParams>([width, height] { return color_stats_params(width, height); }),
  });
}

hand::ShadingSums shading_stats_reference(const HostImage& portrait_color, const HostImage& portrait_depth,
                                          const HostImage& mesh_color, const HostImage& mesh_depth,
                                          const HostImage& mesh_mask, const HostImage& mesh_normal) {
  const ColorStatsParams params = color_stats_params(mesh_color.width, mesh_color.height);
  hand::ShadingSums sums;
  for (uint32_t y = 0; y < mesh_color.height; ++y)
    for (uint32_t x = 0; x < mesh_color.width; ++x) {
      if (!hand_fit_pixel_reference(portrait_color, portrait_depth, mesh_color, mesh_depth, mesh_mask, x, y, params)) continue;
      const Eigen::Vector3d normal(mesh_normal.at(x, y, 0), mesh_normal.at(x, y, 1), mesh_normal.at(x, y, 2));
      const double length_sq = normal.squaredNorm();
      if (!std::isfinite(length_sq) || std::abs(length_sq - 1.0) >= 1e-3) continue;
      const double image = double(portrait_color.at(x, y, 0)) + portrait_color.at(x, y, 1) + portrait_color.at(x, y, 2);
      const double mesh = double(mesh_color.at(x, y, 0)) + mesh_color.at(x, y, 1) + mesh_color.at(x, y, 2);
      sums.add(normal, image / mesh);
    }
  return sums;
}

}  // namespace rt::passes
