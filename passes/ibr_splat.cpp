#include "passes/ibr_splat.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ibr_splat.comp.h"

namespace rt::passes {
namespace {

const SplatSettings& check(const SplatSettings& s) {
  if (!(s.footprint_scale > 0.0f) || !(s.max_footprint_px >= 1.0f) || !(s.average_tolerance_m >= 0.0f))
    throw std::invalid_argument("depth splatting: footprint_scale > 0, max_footprint_px >= 1, average_tolerance_m >= 0");
  return s;
}

std::vector<vk::Knob> knobs(const SplatSettings& s, bool accumulate) {
  return {{"accumulate_average", accumulate},
          {"footprint_scale", s.footprint_scale},
          {"max_footprint_px", s.max_footprint_px},
          {"average_tolerance_m", s.average_tolerance_m}};
}

}  // namespace

vk::BufferDesc fusion_buffer_desc(uint32_t target_width, uint32_t target_height) {
  return {.name = "ibr fusion",
          .size = VkDeviceSize(3) * target_width * target_height * sizeof(uint32_t),
          .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT};
}

IbrSplatPass::IbrSplatPass(vk::Context& context, const SplatSettings& settings)
    : settings_(check(settings)),
      nearest_(context, "ibr_splat", ibr_splat_comp_spirv, knobs(settings, false)),
      average_(context, "ibr_splat_average", ibr_splat_comp_spirv, knobs(settings, true)) {}

void IbrSplatPass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& points, vk::Buffer& fusion,
                          uint32_t view_count) const {
  if (view_count == 0 || points.height() % view_count != 0)
    throw std::invalid_argument("ibr_splat: the points atlas does not hold " + std::to_string(view_count) + " bands");
  const uint32_t pixel_count = uint32_t(fusion.size() / (3 * sizeof(uint32_t)));
  graph.add_pass({
      .name = "ibr_fusion_clear",
      .uses = {{&fusion, vk::access::transfer_write}},
      .record =
          [&fusion, pixel_count](VkCommandBuffer commands) {
            const VkDeviceSize nearest_bytes = VkDeviceSize(pixel_count) * sizeof(uint32_t);
            vkCmdFillBuffer(commands, fusion.buffer(), 0, nearest_bytes, RT_IBR_EMPTY_DEPTH_BITS);
            vkCmdFillBuffer(commands, fusion.buffer(), nearest_bytes, 2 * nearest_bytes, 0u);
          },
  });
  const std::array<uint32_t, 3> threads{points.width(), points.height() / view_count, view_count};
  const std::vector<vk::Binding> bindings{{"points", &points}, {"Fusion", &fusion}, {"IbrSceneTable", &scene.buffer()}};
  graph.add_compute_pass({.name = "ibr_splat", .kernel = &nearest_, .bindings = bindings, .threads = threads});
  if (settings_.fusion == DepthFusion::Average)
    graph.add_compute_pass({.name = "ibr_splat_average", .kernel = &average_, .bindings = bindings, .threads = threads});
}

std::vector<uint32_t> ibr_splat_reference(const IbrSceneTable& table, const HostImage& points, const SplatSettings& s) {
  const int target_width = int(table.target.size[0]), target_height = int(table.target.size[1]);
  const size_t n = size_t(target_width) * size_t(target_height);
  std::vector<uint32_t> fusion(3 * n, 0u);
  std::fill_n(fusion.begin(), n, RT_IBR_EMPTY_DEPTH_BITS);
  // Each splat covers these pixels with this depth; the two passes visit the same splats.
  auto for_each_splat = [&](auto&& visit) {
    for (uint32_t view = 0; view < table.camera_count; ++view) {
      const shader_abi::IbrCamera& camera = table.cameras[view];
      const uint32_t width = uint32_t(camera.depth.tangential[2]), height = uint32_t(camera.depth.tangential[3]);
      for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
          const float* point = &points.texels[points.index(x, y + view * height)];
          if (!(point[3] > 0.0f)) continue;
          const Float3 p = transform_point(table.target.camera_from_site, {point[0], point[1], point[2]});
          if (!(p.z > 1e-4f)) continue;
          const float cx = table.target.pinhole[0] * (p.x / p.z) + table.target.pinhole[2];
          const float cy = table.target.pinhole[1] * (p.y / p.z) + table.target.pinhole[3];
          if (!std::isfinite(cx) || !std::isfinite(cy)) continue;
          if (cx < -s.max_footprint_px || cy < -s.max_footprint_px || cx > table.target.size[0] + s.max_footprint_px ||
              cy > table.target.size[1] + s.max_footprint_px)
            continue;
          const float footprint = s.footprint_scale * (point[3] / camera.depth.pinhole[0]) * table.target.pinhole[0] / p.z;
          const float half_side = 0.5f * std::clamp(footprint, 1.0f, s.max_footprint_px);
          const int x0 = std::max(int(std::ceil(cx - half_side)), 0), y0 = std::max(int(std::ceil(cy - half_side)), 0);
          const int x1 = std::min(int(std::floor(cx + half_side)), target_width - 1);
          const int y1 = std::min(int(std::floor(cy + half_side)), target_height - 1);
          for (int ty = y0; ty <= y1; ++ty)
            for (int tx = x0; tx <= x1; ++tx) visit(size_t(ty) * size_t(target_width) + size_t(tx), p.z);
        }
    }
  };
  for_each_splat([&](size_t index, float z) { fusion[index] = std::min(fusion[index], std::bit_cast<uint32_t>(z)); });
  if (s.fusion == DepthFusion::Average)
    for_each_splat([&](size_t index, float z) {
      if (z <= std::bit_cast<float>(fusion[index]) + s.average_tolerance_m) {
        fusion[n + index] += uint32_t(std::floor(z * 1e5f + 0.5f));
        fusion[2 * n + index] += 1;
      }
    });
  return fusion;
}

}  // namespace rt::passes
