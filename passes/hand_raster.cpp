#include "passes/hand_raster.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "hand/shading_fit.h"
#include "passes/common/reference_raster.h"

#include "hand_raster.frag.h"
#include "hand_raster.vert.h"

namespace rt::passes {
namespace {

struct ClipVertex {
  Eigen::Vector4d clip;
  double u = 0, v = 0, camera_z = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& b, double t) {
  return {a.clip + t * (b.clip - a.clip), a.u + t * (b.u - a.u), a.v + t * (b.v - a.v),
          a.camera_z + t * (b.camera_z - a.camera_z), a.normal + t * (b.normal - a.normal)};
}

}  // namespace

HandRasterParams hand_raster_params(const RasterViewParams& view, const std::array<std::array<float, 4>, 3>& shading) {
  HandRasterParams params{};
  params.view = view;
  for (size_t i = 0; i < 3; ++i) params.shading[i] = shading[i];
  return params;
}

HandRasterPass::HandRasterPass(vk::Context& context)
    : kernel_(context, "hand_raster", hand_raster_vert_spirv, hand_raster_frag_spirv,
              {{PixelFormat::RGBA32F, PixelFormat::R32F, PixelFormat::R32F, PixelFormat::RGBA32F}, true}) {}

void HandRasterPass::add_to(vk::FrameGraph& graph, vk::Buffer& skinned, vk::Buffer& indices,
                            std::function<uint32_t()> index_count, vk::Image& texture, const vk::Sampler& sampler,
                            std::function<HandRasterParams()> params, const HandRasterTargets& targets,
                            const std::string& pass_name) const {
  graph.add_graphics_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"Skinned", &skinned}, {"Indices", &indices}, {"skin_texture", &texture, &sampler}},
      .color = {{targets.color, {0, 0, 0, 0}}, {targets.depth_m, {0, 0, 0, 0}}, {targets.mask, {0, 0, 0, 0}},
                {targets.normal, {0, 0, 0, 0}}},
      .depth = targets.depth_buffer,
      .vertex_count = std::move(index_count),
      .push_constants = vk::push_constants_from<HandRasterParams>(std::move(params)),
  });
}

Eigen::Vector4f sample_bilinear(const HostImage& texture, float u, float v) {
  const float x = u * float(texture.width) - 0.5f, y = v * float(texture.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  auto texel = [&](int tx, int ty) {
    const uint32_t cx = uint32_t(std::clamp(tx, 0, int(texture.width) - 1));
    const uint32_t cy = uint32_t(std::clamp(ty, 0, int(texture.height) - 1));
    Eigen::Vector4f out;
    for (uint32_t c = 0; c < 4; ++c) out[c] = c < texture.channels() ? texture.at(cx, cy, c) : 1.0f;
    return out;
  };
  const int ix = int(fx), iy = int(fy);
  return (1 - ay) * ((1 - ax) * texel(ix, iy) + ax * texel(ix + 1, iy)) +
         ay * ((1 - ax) * texel(ix, iy + 1) + ax * texel(ix + 1, iy + 1));
}

HandRasterReference hand_raster_reference(std::span<const SkinnedVertex> skinned, std::span<const uint32_t> indices,
                                          const HostImage& texture, const HandRasterParams& params, uint32_t width,
                                          uint32_t height) {
  HandRasterReference out{HostImage(width, height, PixelFormat::RGBA32F), HostImage(width, height, PixelFormat::R32F),
                          HostImage(width, height, PixelFormat::R32F), HostImage(width, height, PixelFormat::RGBA32F),
                          HostImage(width, height, PixelFormat::R32F)};
  const RasterViewParams& view = params.view;
  hand::ShadingVector shading;
  for (int k = 0; k < hand::kShadingTerms; ++k) shading[k] = params.shading[size_t(k / 4)][size_t(k % 4)];
  Eigen::Matrix4d clip_from_site;
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row) clip_from_site(row, column) = view.clip_from_site[column * 4 + row];
  std::vector<double> depth_buffer(size_t(width) * height, 1.0);
  // Silhouette edges: only there (and along clipped edges) may the GPU's tie-breaking and the
  // reference differ. An edge is a silhouette when its two triangles face different ways in the
  // image, or it has only one triangle (the texture seams, where vertices are split, count too).
  std::map<std::pair<uint32_t, uint32_t>, std::vector<int>> edge_facing;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> marked;
  std::vector<std::array<Eigen::Vector2d, 3>> unclipped(indices.size() / 3);

  for (size_t first = 0; first + 2 < indices.size(); first += 3) {
    std::vector<ClipVertex> polygon;
    bool finite = true;
    for (size_t i = first; i < first + 3; ++i) {
      const SkinnedVertex& v = skinned[indices[i]];
      const Eigen::Vector4d site(v.position_u[0], v.position_u[1], v.position_u[2], 1.0);
      ClipVertex c;
      c.clip = clip_from_site * site;
      c.u = v.position_u[3];
      c.v = v.normal_v[3];
      c.camera_z = view.depth_row[0] * site.x() + view.depth_row[1] * site.y() + view.depth_row[2] * site.z() + view.depth_row[3];
      c.normal = Eigen::Vector3d(v.normal_v[0], v.normal_v[1], v.normal_v[2]);
      finite &= c.clip.allFinite();
      polygon.push_back(c);
    }
    if (!finite) continue;
    bool clipped = false;
    for (const ClipVertex& v : polygon) clipped |= v.clip.z() < 0 || v.clip.z() > v.clip.w();
    polygon = clip_polygon(polygon, [](const ClipVertex& v) { return v.clip.z(); });
    polygon = clip_polygon(polygon, [](const ClipVertex& v) { return v.clip.w() - v.clip.z(); });
    if (polygon.size() < 3) continue;
    std::vector<Eigen::Vector3d> screen;
    for (const ClipVertex& v : polygon) {
      const Eigen::Vector3d ndc = v.clip.head<3>() / v.clip.w();
      screen.emplace_back((ndc.x() + 1) * 0.5 * width, (ndc.y() + 1) * 0.5 * height, ndc.z());
    }
    if (clipped || polygon.size() != 3) {
      for (size_t e = 0; e < screen.size(); ++e)
        marked.emplace_back(screen[e].head<2>(), screen[(e + 1) % screen.size()].head<2>());
    } else {
      const Eigen::Vector2d a = screen[0].head<2>(), b = screen[1].head<2>(), c = screen[2].head<2>();
      const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      unclipped[first / 3] = {a, b, c};
      for (int e = 0; e < 3; ++e) {
        const uint32_t i = indices[first + size_t(e)], j = indices[first + size_t((e + 1) % 3)];
        edge_facing[{std::min(i, j), std::max(i, j)}].push_back(area > 0 ? 1 : area < 0 ? -1 : 0);
      }
    }
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      const size_t ids[3] = {0, k, k + 1};
      const Eigen::Vector2d a = screen[ids[0]].head<2>(), b = screen[ids[1]].head<2>(), c = screen[ids[2]].head<2>();
      for_each_pixel_near_triangle(a, b, c, width, height, [&](int x, int y, const Eigen::Vector2d&, double w0,
                                                                 double w1, double w2) {
          const auto weights = depth_tested_weights(
              {w0, w1, w2}, {screen[ids[0]].z(), screen[ids[1]].z(), screen[ids[2]].z()},
              {polygon[ids[0]].clip.w(), polygon[ids[1]].clip.w(), polygon[ids[2]].clip.w()},
              depth_buffer[size_t(y) * width + x]);
          if (!weights) return;
          auto interpolate = [&](auto get) {
            return (*weights)[0] * get(polygon[ids[0]]) + (*weights)[1] * get(polygon[ids[1]]) +
                   (*weights)[2] * get(polygon[ids[2]]);
          };
          const Eigen::Vector4f color = sample_bilinear(texture, float(interpolate([](const ClipVertex& v) { return v.u; })),
                                                         float(interpolate([](const ClipVertex& v) { return v.v; })));
          const Eigen::Vector3d normal = (*weights)[0] * polygon[ids[0]].normal + (*weights)[1] * polygon[ids[1]].normal +
                                         (*weights)[2] * polygon[ids[2]].normal;
          const double length_sq = normal.squaredNorm();
          const bool has_normal = std::isfinite(length_sq) && length_sq > 1e-12;
          const double s = has_normal ? hand::shade(shading, normal) : 1.0;
          for (uint32_t channel = 0; channel < 3; ++channel) {
            out.color.at(uint32_t(x), uint32_t(y), channel) = std::clamp(float(color[channel] * s), 0.0f, 1.0f);
            out.normal.at(uint32_t(x), uint32_t(y), channel) = has_normal ? float(normal[channel] / std::sqrt(length_sq)) : 0.0f;
          }
          out.normal.at(uint32_t(x), uint32_t(y), 3) = has_normal ? 1.0f : 0.0f;
          out.color.at(uint32_t(x), uint32_t(y), 3) = 1.0f;
          out.depth_m.at(uint32_t(x), uint32_t(y)) = float(interpolate([](const ClipVertex& v) { return v.camera_z; }));
          out.mask.at(uint32_t(x), uint32_t(y)) = 1.0f;
        });
    }
  }
  // Mark pixels within one pixel of a silhouette or clipped edge.
  for (size_t first = 0; first + 2 < indices.size(); first += 3)
    for (int e = 0; e < 3; ++e) {
      const uint32_t i = indices[first + size_t(e)], j = indices[first + size_t((e + 1) % 3)];
      const auto found = edge_facing.find({std::min(i, j), std::max(i, j)});
      if (found == edge_facing.end()) continue;
      const auto& facing = found->second;
      if (facing.size() == 2 && facing[0] == facing[1] && facing[0] != 0) continue;
      marked.emplace_back(unclipped[first / 3][size_t(e)], unclipped[first / 3][size_t((e + 1) % 3)]);
    }
  for (const auto& [a, b] : marked) {
    if (!a.allFinite() || !b.allFinite()) continue;
    const int x0 = std::max(0, int(std::floor(std::min(a.x(), b.x()))) - 2);
    const int x1 = std::min(int(width) - 1, int(std::ceil(std::max(a.x(), b.x()))) + 2);
    const int y0 = std::max(0, int(std::floor(std::min(a.y(), b.y()))) - 2);
    const int y1 = std::min(int(height) - 1, int(std::ceil(std::max(a.y(), b.y()))) + 2);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (distance_to_segment(Eigen::Vector2d(x + 0.5, y + 0.5), a, b) <= 1.0) out.near_edge.at(uint32_t(x), uint32_t(y)) = 1.0f;
  }
  return out;
}

}  // namespace rt::passes
