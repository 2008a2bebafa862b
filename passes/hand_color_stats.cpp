#include "passes/hand_color_stats.h"

#include <cmath>

#include "hand/color_space.h"
#include "hand_color_stats.comp.h"

namespace rt::passes {

ColorStatsParams color_stats_params(uint32_t width, uint32_t height) {
  return {width * height, width, float(RT_APPEARANCE_DEPTH_TOLERANCE_M), kBlackLevel, kSaturatedLevel};
}

uint32_t color_stats_group_count(uint32_t width, uint32_t height) {
  const uint32_t per_group = RT_COLOR_STATS_GROUP * RT_COLOR_STATS_PIXELS_PER_THREAD;
  return (width * height + per_group - 1) / per_group;
}

HandColorStatsPass::HandColorStatsPass(vk::Context& context) : kernel_(context, "hand_color_stats", hand_color_stats_comp_spirv) {}

void HandColorStatsPass::add_to(vk::FrameGraph& graph, vk::Image& portrait_color, vk::Image& portrait_depth,
                                vk::Image& mesh_color, vk::Image& mesh_depth, vk::Image& mesh_mask, vk::Buffer& partials,
                                const std::string& pass_name) const {
  const uint32_t width = mesh_color.width(), height = mesh_color.height();
  for (vk::Image* image : {&portrait_color, &portrait_depth, &mesh_depth, &mesh_mask})
    if (image->width() != width || image->height() != height)
      throw std::invalid_argument("pass '" + pass_name + "': image '" + image->name() + "' differs in size from '" +
                                  mesh_color.name() + "'");
  if (partials.size() < color_stats_group_count(width, height) * sizeof(ColorStatsPartial))
    throw std::invalid_argument("pass '" + pass_name + "': buffer '" + partials.name() + "' is too small");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"portrait_color", &portrait_color}, {"portrait_depth", &portrait_depth}, {"mesh_color", &mesh_color},
                   {"mesh_depth", &mesh_depth}, {"mesh_mask", &mesh_mask}, {"Partials", &partials}},
      .threads = {color_stats_group_count(width, height) * RT_COLOR_STATS_GROUP, 1, 1},
      .push_constants = vk::push_constants_from<ColorStatsParams>([width, height] { return color_stats_params(width, height); }),
  });
}

bool hand_fit_pixel_reference(const HostImage& portrait_color, const HostImage& portrait_depth, const HostImage& mesh_color,
                              const HostImage& mesh_depth, const HostImage& mesh_mask, uint32_t x, uint32_t y,
                              const ColorStatsParams& params) {
  auto usable = [&](const HostImage& color) {
    const Eigen::Vector3d c(color.at(x, y, 0), color.at(x, y, 1), color.at(x, y, 2));
    return c.allFinite() && (c.array() > params.min_level).all() && (c.array() < params.max_level).all();
  };
  const float di = portrait_depth.at(x, y), dg = mesh_depth.at(x, y);
  return mesh_mask.at(x, y) > 0.5f && portrait_color.at(x, y, 3) > 0.5f && std::isfinite(di) && std::isfinite(dg) &&
         di > 0 && dg > 0 && std::abs(di - dg) < params.depth_tolerance_m && usable(portrait_color) && usable(mesh_color);
}

ColorSums color_stats_reference(const HostImage& portrait_color, const HostImage& portrait_depth, const HostImage& mesh_color,
                                const HostImage& mesh_depth, const HostImage& mesh_mask, const ColorStatsParams& params) {
  ColorSums sums;
  for (uint32_t y = 0; y < mesh_color.height; ++y)
    for (uint32_t x = 0; x < mesh_color.width; ++x) {
      if (!hand_fit_pixel_reference(portrait_color, portrait_depth, mesh_color, mesh_depth, mesh_mask, x, y, params)) continue;
      const Eigen::Vector3d image(portrait_color.at(x, y, 0), portrait_color.at(x, y, 1), portrait_color.at(x, y, 2));
      const Eigen::Vector3d mesh(mesh_color.at(x, y, 0), mesh_color.at(x, y, 1), mesh_color.at(x, y, 2));
      const Eigen::Vector3d li = hand::rgb_to_lab_alpha_beta(image), lg = hand::rgb_to_lab_alpha_beta(mesh);
      sums.count += 1;
      sums.image_sum += li;
      sums.image_sum_sq += li.cwiseProduct(li);
      sums.mesh_sum += lg;
      sums.mesh_sum_sq += lg.cwiseProduct(lg);
    }
  return sums;
}

}  // namespace rt::passes
