#include "passes/depth_in_color.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "depth_in_color.comp.h"
#include "geometry/pixel_rays.h"
#include "passes/common/ibr_scene.h"
#include "passes/common/lens.h"

namespace rt::passes {
namespace {

const DepthInColorSettings& check(const DepthInColorSettings& s) {
  if (!(s.max_jump_m >= 0.0f) || !(s.max_jump_relative >= 0.0f) || !(s.max_triangle_px >= 1.0f) ||
      !std::isfinite(s.max_jump_m) || !std::isfinite(s.max_jump_relative) || !std::isfinite(s.max_triangle_px))
    throw std::invalid_argument("depth_in_color: needs finite max_jump_m >= 0, max_jump_relative >= 0, max_triangle_px >= 1");
  return s;
}

std::vector<vk::Knob> knobs(const DepthInColorSettings& s, bool resolve) {
  return {{"resolve", resolve},
          {"max_jump_m", s.max_jump_m},
          {"max_jump_relative", s.max_jump_relative},
          {"max_triangle_px", s.max_triangle_px}};
}

// The largest x^2 + y^2 (on z = 1) that the colour lens maps into its image, with a tenth more
// radius to spare: the image's border undistorted, every few pixels.
float lens_field(const CameraIntrinsics& k) {
  std::vector<std::array<double, 2>> border;
  const double w = k.width - 1.0, h = k.height - 1.0;
  for (int i = 0; i <= 64; ++i) {
    const double t = i / 64.0;
    border.insert(border.end(), {{t * w, 0}, {t * w, h}, {0, t * h}, {w, t * h}});
  }
  const std::vector<std::array<double, 2>> normalised = undistorted_points(k, border);
  double largest = 0;
  for (const auto& [x, y] : normalised)
    if (std::isfinite(x) && std::isfinite(y)) largest = std::max(largest, x * x + y * y);
  // No border point undistorted (a lens OpenCV cannot invert there): no limit rather than no image.
  return largest > 0 ? float(largest * 1.21) : std::numeric_limits<float>::max();
}

}  // namespace

shader_abi::DepthInColorParams depth_in_color_params(const CameraIntrinsics& color, const Eigen::Isometry3d& color_from_depth) {
  const Distortion& d = color.distortion;
  const double values[] = {color.fx, color.fy, color.cx, color.cy, d.k1, d.k2, d.k3, d.k4, d.k5, d.k6, d.p1, d.p2};
  if (color.width == 0 || color.height == 0 || !std::all_of(std::begin(values), std::end(values), [](double v) {
        return std::isfinite(v);
      }) || !(color.fx > 0 && color.fy > 0) || !color_from_depth.matrix().allFinite())
    throw std::invalid_argument("depth_in_color: the colour camera needs a size, fx, fy > 0 and finite parameters, "
                                "and colour_from_depth finite values");
  shader_abi::DepthInColorParams params{};
  const Eigen::Matrix4d m = color_from_depth.matrix();
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 4; ++column) params.color_from_depth[row][size_t(column)] = float(m(row, column));
  params.color = lens_of(color);
  params.field = {lens_field(color), 0.0f, 0.0f, 0.0f};
  return params;
}

std::vector<float> depth_in_color_rays(const CameraIntrinsics& depth) {
  const std::vector<std::array<float, 2>> rays = undistorted_pixel_rays(depth);
  std::vector<float> out;
  out.reserve(2 * rays.size());
  for (const auto& ray : rays) out.insert(out.end(), {ray[0], ray[1]});
  return out;
}

vk::BufferDesc depth_in_color_rays_desc(uint32_t depth_width, uint32_t depth_height) {
  return {.name = "depth_in_color rays",
          .size = VkDeviceSize(2) * depth_width * depth_height * sizeof(float),
          .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT};
}

vk::BufferDesc depth_in_color_nearest_desc(uint32_t color_width, uint32_t color_height) {
  return {.name = "depth_in_color nearest",
          .size = VkDeviceSize(color_width) * color_height * sizeof(uint32_t),
          .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT};
}

DepthInColorPass::DepthInColorPass(vk::Context& context, const DepthInColorSettings& settings)
    : settings_(check(settings)),
      splat_(context, "depth_in_color", depth_in_color_comp_spirv, knobs(settings, false)),
      resolve_(context, "depth_in_color_resolve", depth_in_color_comp_spirv, knobs(settings, true)) {}

void DepthInColorPass::add_to(vk::FrameGraph& graph, vk::Image& depth_mm, vk::Buffer& rays, vk::Buffer& nearest,
                              vk::Image& depth_in_color, std::function<shader_abi::DepthInColorParams()> params,
                              const std::string& pass_name) const {
  const uint32_t dw = depth_mm.width(), dh = depth_mm.height(), cw = depth_in_color.width(), ch = depth_in_color.height();
  if (rays.size() < depth_in_color_rays_desc(dw, dh).size)
    throw std::invalid_argument(pass_name + ": the rays buffer holds fewer rays than the depth image has pixels");
  if (nearest.size() < depth_in_color_nearest_desc(cw, ch).size)
    throw std::invalid_argument(pass_name + ": the nearest buffer is smaller than the colour image");
  // The colour size is the shader's from the push constants: a frame whose camera differs from
  // the output would write out of bounds, so it fails loudly when recorded.
  auto checked = [params = std::move(params), cw, ch, pass_name] {
    const shader_abi::DepthInColorParams p = params();
    if (p.color.tangential[2] != float(cw) || p.color.tangential[3] != float(ch))
      throw std::logic_error(pass_name + ": the colour camera's size differs from the output image's");
    return p;
  };
  const VkDeviceSize bytes = depth_in_color_nearest_desc(cw, ch).size;
  graph.add_pass({.name = pass_name + "_clear",
                  .uses = {{&nearest, vk::access::transfer_write}},
                  .record = [&nearest, bytes](VkCommandBuffer commands) {
                    vkCmdFillBuffer(commands, nearest.buffer(), 0, bytes, RT_DEPTH_IN_COLOR_EMPTY);
                  }});
  const std::vector<vk::Binding> bindings{
      {"depth_mm", &depth_mm}, {"Rays", &rays}, {"Nearest", &nearest}, {"depth_in_color", &depth_in_color}};
  // A cell joins a pixel to its neighbours right and below: none in a single row or column.
  if (dw >= 2 && dh >= 2)
    graph.add_compute_pass({.name = pass_name,
                            .kernel = &splat_,
                            .bindings = bindings,
                            .threads = {dw - 1, dh - 1, 1},
                            .push_constants = vk::push_constants_from<shader_abi::DepthInColorParams>(checked)});
  graph.add_compute_pass({.name = pass_name + "_resolve",
                          .kernel = &resolve_,
                          .bindings = bindings,
                          .threads = {cw, ch, 1},
                          .push_constants = vk::push_constants_from<shader_abi::DepthInColorParams>(checked)});
}

namespace {

struct Vertex {
  Float2 pixel;
  float color_z = 0, depth_z = 0;
};

float dot4(const std::array<float, 4>& row, const std::array<float, 4>& p) {
  return row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3] * p[3];
}

}  // namespace

HostImage depth_in_color_reference(const HostImage& depth_mm, std::span<const float> rays,
                                   const shader_abi::DepthInColorParams& params, const DepthInColorSettings& s) {
  check(s);
  const int dw = int(depth_mm.width), dh = int(depth_mm.height);
  const int cw = int(params.color.tangential[2]), ch = int(params.color.tangential[3]);
  if (rays.size() < 2 * size_t(dw) * size_t(dh)) throw std::invalid_argument("depth_in_color_reference: too few rays");
  std::vector<uint32_t> nearest(size_t(cw) * size_t(ch), RT_DEPTH_IN_COLOR_EMPTY);

  // The shader's vertex_at.
  auto vertex_at = [&](int x, int y, Vertex& v) {
    v = {};
    const float millimetres = depth_mm.at(uint32_t(x), uint32_t(y));
    if (millimetres == 0.0f) return false;
    const size_t i = size_t(y) * size_t(dw) + size_t(x);
    const float rx = rays[2 * i], ry = rays[2 * i + 1];
    if (!std::isfinite(rx) || !std::isfinite(ry)) return false;
    const float z = millimetres * 0.001f;
    const std::array<float, 4> point{rx * z, ry * z, z, 1.0f};
    const float cx = dot4(params.color_from_depth[0], point), cy = dot4(params.color_from_depth[1], point);
    const float cz = dot4(params.color_from_depth[2], point);
    if (!(cz > float(RT_DEPTH_IN_COLOR_NEAR_M))) return false;
    const Float2 xy{cx / cz, cy / cz};
    if (!(xy.x * xy.x + xy.y * xy.y <= params.field[0])) return false;
    v.pixel = lens_pixel(params.color, xy);
    v.color_z = cz;
    v.depth_z = z;
    return std::isfinite(v.pixel.x) && std::isfinite(v.pixel.y);
  };
  auto one_surface = [&](float low, float high) { return high - low <= s.max_jump_m + s.max_jump_relative * low; };
  auto one_surface3 = [&](const Vertex& a, const Vertex& b, const Vertex& c) {
    return one_surface(std::min({a.depth_z, b.depth_z, c.depth_z}), std::max({a.depth_z, b.depth_z, c.depth_z}));
  };
  // The shader's splat_triangle.
  auto splat = [&](const Vertex& a, const Vertex& b, const Vertex& c) {
    const float area = (b.pixel.x - a.pixel.x) * (c.pixel.y - a.pixel.y) - (b.pixel.y - a.pixel.y) * (c.pixel.x - a.pixel.x);
    if (!(std::abs(area) > 1e-12f)) return;
    const float low_x = std::min({a.pixel.x, b.pixel.x, c.pixel.x}), high_x = std::max({a.pixel.x, b.pixel.x, c.pixel.x});
    const float low_y = std::min({a.pixel.y, b.pixel.y, c.pixel.y}), high_y = std::max({a.pixel.y, b.pixel.y, c.pixel.y});
    if (high_x - low_x > s.max_triangle_px || high_y - low_y > s.max_triangle_px) return;
    if (high_x < 0.0f || high_y < 0.0f || low_x > float(cw - 1) || low_y > float(ch - 1)) return;
    const int x0 = std::max(int(std::ceil(low_x - 0.01f)), 0), y0 = std::max(int(std::ceil(low_y - 0.01f)), 0);
    const int x1 = std::min(int(std::floor(high_x + 0.01f)), cw - 1);
    const int y1 = std::min(int(std::floor(high_y + 0.01f)), ch - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const float px = float(x), py = float(y);
        const float wa = ((b.pixel.x - px) * (c.pixel.y - py) - (b.pixel.y - py) * (c.pixel.x - px)) / area;
        const float wb = ((c.pixel.x - px) * (a.pixel.y - py) - (c.pixel.y - py) * (a.pixel.x - px)) / area;
        const float wc = 1.0f - wa - wb;
        if (wa < -1e-4f || wb < -1e-4f || wc < -1e-4f) continue;
        const float z = wa * a.color_z + wb * b.color_z + wc * c.color_z;
        const uint32_t millimetres = uint32_t(std::clamp(std::floor(z * 1000.0f + 0.5f), 1.0f, 65535.0f));
        uint32_t& slot = nearest[size_t(y) * size_t(cw) + size_t(x)];
        slot = std::min(slot, millimetres);
      }
  };
  for (int y = 0; y + 1 < dh; ++y)
    for (int x = 0; x + 1 < dw; ++x) {
      Vertex v00, v10, v01, v11;
      const bool h00 = vertex_at(x, y, v00), h10 = vertex_at(x + 1, y, v10);
      const bool h01 = vertex_at(x, y + 1, v01), h11 = vertex_at(x + 1, y + 1, v11);
      if (h00 && h10 && h01 && h11 &&
          one_surface(std::min({v00.depth_z, v10.depth_z, v01.depth_z, v11.depth_z}),
                      std::max({v00.depth_z, v10.depth_z, v01.depth_z, v11.depth_z}))) {
        splat(v00, v10, v11);
        splat(v00, v11, v01);
        continue;
      }
      if (h00 && h10 && h01 && one_surface3(v00, v10, v01)) splat(v00, v10, v01);
      if (h10 && h11 && h01 && one_surface3(v10, v11, v01)) splat(v10, v11, v01);
      if (h00 && h10 && h11 && one_surface3(v00, v10, v11)) splat(v00, v10, v11);
      if (h00 && h11 && h01 && one_surface3(v00, v11, v01)) splat(v00, v11, v01);
    }
  HostImage out(uint32_t(cw), uint32_t(ch), PixelFormat::R16U);
  for (size_t i = 0; i < nearest.size(); ++i) out.texels[i] = nearest[i] == RT_DEPTH_IN_COLOR_EMPTY ? 0.0f : float(nearest[i]);
  return out;
}

}  // namespace rt::passes
