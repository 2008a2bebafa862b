#include "passes/ibr_splat.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "ibr_splat.comp.h"

namespace rt::passes {
namespace {

const SplatSettings& check(const SplatSettings& s) {
  if (!(s.footprint_scale > 0.0f) || !(s.max_footprint_px >= 1.0f) || !(s.average_tolerance_m >= 0.0f) ||
      !(s.plane_tolerance_m >= 0.0f) || !(s.edge_inset >= 0.0f && s.edge_inset < 0.5f))
    throw std::invalid_argument(
        "depth splatting: footprint_scale > 0, max_footprint_px >= 1, average_tolerance_m >= 0, plane_tolerance_m >= 0, "
        "0 <= edge_inset < 0.5");
  return s;
}

std::vector<vk::Knob> knobs(const SplatSettings& s, bool accumulate) {
  return {{"accumulate_average", accumulate},
          {"footprint_scale", s.footprint_scale},
          {"max_footprint_px", s.max_footprint_px},
          {"average_tolerance_m", s.average_tolerance_m},
          {"plane_tolerance_m", s.plane_tolerance_m},
          {"edge_inset", s.edge_inset}};
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

void IbrSplatPass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& points, IbrTiles& point_tiles,
                          vk::Buffer& fusion, uint32_t view_count) const {
  if (view_count == 0 || points.height() % view_count != 0)
    throw std::invalid_argument("ibr_splat: the points atlas does not hold " + std::to_string(view_count) + " bands");
  if (point_tiles.layers() != view_count || !point_tiles.lists_bands_of(points))
    throw std::invalid_argument("ibr_splat: the tile list is not one of " + std::to_string(view_count) +
                                " views of the points atlas's bands");
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
  const std::vector<vk::Binding> bindings{
      {"points", &points}, {"Fusion", &fusion}, {"IbrSceneTable", &scene.buffer()}, {"Tiles", &point_tiles.tiles()}};
  vk::Buffer* dispatch = &point_tiles.dispatch();
  graph.add_compute_pass({.name = "ibr_splat", .kernel = &nearest_, .bindings = bindings, .indirect = dispatch});
  if (settings_.fusion == DepthFusion::Average)
    graph.add_compute_pass({.name = "ibr_splat_average", .kernel = &average_, .bindings = bindings, .indirect = dispatch});
}

namespace {

struct Projected {
  float x = 0, y = 0, z = 0;
};

// The shader's project_point: where a foreground point lands in the target view.
std::optional<Projected> project_point(const IbrSceneTable& table, const HostImage& points, int x, int y, uint32_t view,
                                       int width, int height) {
  if (x < 0 || y < 0 || x >= width || y >= height) return std::nullopt;
  const float* point = &points.texels[points.index(uint32_t(x), uint32_t(y) + view * uint32_t(height))];
  if (!(point[3] > 0.0f)) return std::nullopt;
  const Float3 p = transform_point(table.target.camera_from_site, {point[0], point[1], point[2]});
  if (!(p.z > 1e-4f)) return std::nullopt;
  const Projected projected{table.target.pinhole[0] * (p.x / p.z) + table.target.pinhole[2],
                            table.target.pinhole[1] * (p.y / p.z) + table.target.pinhole[3], p.z};
  if (!std::isfinite(projected.x) || !std::isfinite(projected.y)) return std::nullopt;
  return projected;
}

// The shader's surface_neighbour: the offset to the neighbour at (x, y) when it lies on the same
// surface as `centre`.
std::optional<Projected> surface_neighbour(const IbrSceneTable& table, const HostImage& points, int x, int y,
                                           uint32_t view, int width, int height, Projected centre, float tolerance) {
  const auto q = project_point(table, points, x, y, view, width, height);
  if (!q || std::abs(q->z - centre.z) > tolerance) return std::nullopt;
  return Projected{q->x - centre.x, q->y - centre.y, q->z - centre.z};
}

Projected negated(const Projected& p) { return {-p.x, -p.y, -p.z}; }

// The shader's spans_area: two steps across the surface that the eye does not see edge-on.
bool spans_area(const Projected& u, const Projected& v) {
  const float det = u.x * v.y - u.y * v.x;
  return std::abs(det) > 0.01f * std::hypot(u.x, u.y) * std::hypot(v.x, v.y) && std::abs(det) > 1e-8f;
}

// The shader's quarter_depth: the depth at offset (ox, oy) from the splat's centre at depth z0
// on the first quarter that holds it. Steps and limits in the order right, left, below, above.
std::optional<float> quarter_depth(float ox, float oy, float z0, const std::array<Projected, 4>& steps,
                                   const std::array<float, 4>& limits) {
  for (int quarter = 0; quarter < 4; ++quarter) {
    const bool to_x_left = (quarter & 1) != 0, to_y_above = (quarter & 2) != 0;
    const Projected& x_step = steps[to_x_left ? 1 : 0];
    const Projected& y_step = steps[to_y_above ? 3 : 2];
    if (!spans_area(x_step, y_step)) continue;
    const float det = x_step.x * y_step.y - x_step.y * y_step.x;
    const float a = (ox * y_step.y - oy * y_step.x) / det;
    const float b = (x_step.x * oy - x_step.y * ox) / det;
    if (a < -1e-4f || b < -1e-4f || a > limits[to_x_left ? 1 : 0] || b > limits[to_y_above ? 3 : 2]) continue;
    return std::max(z0 + a * x_step.z + b * y_step.z, 1e-4f);
  }
  return std::nullopt;
}

}  // namespace

std::vector<uint32_t> ibr_splat_reference(const IbrSceneTable& table, const HostImage& points, const SplatSettings& s) {
  check(s);
  const int target_width = int(table.target.size[0]), target_height = int(table.target.size[1]);
  const size_t n = size_t(target_width) * size_t(target_height);
  std::vector<uint32_t> fusion(3 * n, 0u);
  std::fill_n(fusion.begin(), n, RT_IBR_EMPTY_DEPTH_BITS);
  // Each splat covers these pixels with these depths; the two passes visit the same splats.
  auto for_each_splat = [&](auto&& visit) {
    for (uint32_t view = 0; view < table.camera_count; ++view) {
      const shader_abi::IbrCamera& camera = table.cameras[view];
      const int width = int(camera.depth.tangential[2]), height = int(camera.depth.tangential[3]);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const auto centre = project_point(table, points, x, y, view, width, height);
          if (!centre) continue;
          if (centre->x < -s.max_footprint_px || centre->y < -s.max_footprint_px ||
              centre->x > table.target.size[0] + s.max_footprint_px || centre->y > table.target.size[1] + s.max_footprint_px)
            continue;
          auto neighbour = [&](int nx, int ny) {
            return surface_neighbour(table, points, nx, ny, view, width, height, *centre, s.plane_tolerance_m);
          };
          const auto right = neighbour(x + 1, y), left = neighbour(x - 1, y);
          const auto below = neighbour(x, y + 1), above = neighbour(x, y - 1);
          // The shader's steps each way along each axis (a missing side mirrors the other).
          const Projected step_right = right ? *right : left ? negated(*left) : Projected{};
          const Projected step_left = left ? *left : right ? negated(*right) : Projected{};
          const Projected step_below = below ? *below : above ? negated(*above) : Projected{};
          const Projected step_above = above ? *above : below ? negated(*below) : Projected{};
          const bool on_surface = (right || left) && (below || above) && spans_area(step_right, step_below);
          float half_x, half_y;
          if (on_surface) {
            half_x = std::min(0.5f * s.footprint_scale *
                                  (std::max(std::abs(step_right.x), std::abs(step_left.x)) +
                                   std::max(std::abs(step_below.x), std::abs(step_above.x))),
                              0.5f * s.max_footprint_px);
            half_y = std::min(0.5f * s.footprint_scale *
                                  (std::max(std::abs(step_right.y), std::abs(step_left.y)) +
                                   std::max(std::abs(step_below.y), std::abs(step_above.y))),
                              0.5f * s.max_footprint_px);
          } else {
            const float depth = points.texels[points.index(uint32_t(x), uint32_t(y) + view * uint32_t(height)) + 3];
            const float footprint = s.footprint_scale * (depth / camera.depth.pinhole[0]) * table.target.pinhole[0] / centre->z;
            half_x = half_y = 0.5f * std::clamp(footprint, 1.0f, s.max_footprint_px);
          }
          const int x0 = std::max(int(std::ceil(centre->x - half_x)), 0), y0 = std::max(int(std::ceil(centre->y - half_y)), 0);
          const int x1 = std::min(int(std::floor(centre->x + half_x)), target_width - 1);
          const int y1 = std::min(int(std::floor(centre->y + half_y)), target_height - 1);
          const float limit = 0.5f * s.footprint_scale + 1e-3f;
          auto side_limit = [&](const std::optional<Projected>& side) { return side ? limit : limit - s.edge_inset; };
          const std::array<float, 4> limits{side_limit(right), side_limit(left), side_limit(below), side_limit(above)};
          const std::array<Projected, 4> steps{step_right, step_left, step_below, step_above};
          for (int ty = y0; ty <= y1; ++ty)
            for (int tx = x0; tx <= x1; ++tx) {
              float z = centre->z;
              if (on_surface) {
                const auto quarter = quarter_depth(float(tx) - centre->x, float(ty) - centre->y, centre->z, steps, limits);
                if (!quarter) continue;
                z = *quarter;
              }
              visit(size_t(ty) * size_t(target_width) + size_t(tx), z);
            }
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
