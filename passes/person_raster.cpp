#include "passes/person_raster.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "passes/common/reference_raster.h"
#include "passes/hand_raster.h"

#include "person_raster.frag.h"
#include "person_raster.vert.h"

namespace rt::passes {
namespace {

constexpr float kLight[3] = {0.2672612f, 0.5345225f, 0.8017837f};  // as in person_raster.frag

// A vertex in clip space with the attributes the fragment shader interpolates.
struct PersonClipVertex {
  Eigen::Vector4d clip;
  std::array<double, 13> attributes;  // site position 3, normal 3, albedo 3, stripe 4 (rgb, period)
  double camera_z = 0;
};

PersonClipVertex lerp(const PersonClipVertex& a, const PersonClipVertex& b, double t) {
  PersonClipVertex out;
  out.clip = a.clip + t * (b.clip - a.clip);
  for (size_t i = 0; i < a.attributes.size(); ++i) out.attributes[i] = a.attributes[i] + t * (b.attributes[i] - a.attributes[i]);
  out.camera_z = a.camera_z + t * (b.camera_z - a.camera_z);
  return out;
}

}  // namespace

RasterViewParams raster_view(const Camera& camera, double near_m, double far_m) {
  if (!(near_m > 0) || !(far_m > near_m)) throw std::invalid_argument("raster view needs 0 < near < far");
  const CameraIntrinsics& k = camera.intrinsics;
  const double w = k.width, h = k.height;
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = 2 * k.fx / w;
  projection(0, 2) = 2 * (k.cx + 0.5) / w - 1;
  projection(1, 1) = 2 * k.fy / h;
  projection(1, 2) = 2 * (k.cy + 0.5) / h - 1;
  projection(2, 2) = far_m / (far_m - near_m);
  projection(2, 3) = -far_m * near_m / (far_m - near_m);
  projection(3, 2) = 1;
  const Eigen::Matrix4d clip_from_site = projection * camera.camera_from_site.matrix();
  RasterViewParams view{};
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row) view.clip_from_site[column * 4 + row] = float(clip_from_site(row, column));
  for (int i = 0; i < 4; ++i) view.depth_row[i] = float(camera.camera_from_site.matrix()(2, i));
  return view;
}

PersonRasterPass::PersonRasterPass(vk::Context& context)
    : kernel_(context, "person_raster", person_raster_vert_spirv, person_raster_frag_spirv,
              {{PixelFormat::RGBA8, PixelFormat::R32F, PixelFormat::R32F}, true}),
      blank_face_(context, {"blank face texture", 1, 1, PixelFormat::RGBA32F}),
      sampler_(context, "face texture sampler") {
  vk::upload(context, blank_face_, HostImage(1, 1, PixelFormat::RGBA32F, 0.0f));
}

void PersonRasterPass::add_to(vk::FrameGraph& graph, vk::Buffer& mesh, std::function<uint32_t()> vertex_count,
                              std::function<RasterViewParams()> view, const RasterTargets& targets,
                              const std::string& pass_name, vk::Image* face_texture) const {
  vk::Image* face = face_texture ? face_texture : &blank_face_;
  graph.add_graphics_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"Mesh", &mesh}, {"face_texture", face, &sampler_}},
      .color = {{targets.color, {0, 0, 0, 0}}, {targets.depth_m, {0, 0, 0, 0}}, {targets.part, {0, 0, 0, 0}}},
      .depth = targets.depth_buffer,
      .vertex_count = std::move(vertex_count),
      .push_constants = vk::push_constants_from<RasterViewParams>(std::move(view)),
  });
}

RasterReference person_raster_reference(std::span<const MeshVertex> mesh, const RasterViewParams& view, uint32_t width,
                                        uint32_t height, const HostImage* face_texture) {
  RasterReference out{HostImage(width, height, PixelFormat::RGBA8), HostImage(width, height, PixelFormat::R32F),
                      HostImage(width, height, PixelFormat::R32F), HostImage(width, height, PixelFormat::R32F)};
  Eigen::Matrix4d clip_from_site;
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row) clip_from_site(row, column) = view.clip_from_site[column * 4 + row];
  std::vector<double> depth_buffer(size_t(width) * height, 1.0);

  for (size_t first = 0; first + 2 < mesh.size(); first += 3) {
    std::vector<PersonClipVertex> polygon;
    bool finite = true;
    for (size_t i = first; i < first + 3; ++i) {
      const MeshVertex& v = mesh[i];
      PersonClipVertex c;
      const Eigen::Vector4d site(v.position_part[0], v.position_part[1], v.position_part[2], 1.0);
      c.clip = clip_from_site * site;
      c.camera_z = view.depth_row[0] * site.x() + view.depth_row[1] * site.y() + view.depth_row[2] * site.z() + view.depth_row[3];
      const float attributes[13] = {v.position_part[0], v.position_part[1], v.position_part[2], v.normal_stripe[0],
                                    v.normal_stripe[1], v.normal_stripe[2], v.color[0], v.color[1], v.color[2],
                                    v.stripe_color[0], v.stripe_color[1], v.stripe_color[2], v.normal_stripe[3]};
      for (int a = 0; a < 13; ++a) c.attributes[a] = attributes[a];
      finite &= c.clip.allFinite();
      polygon.push_back(c);
    }
    if (!finite) continue;
    const float part = mesh[first].position_part[3];  // Vulkan's provoking vertex: the first
    polygon = clip_polygon(polygon, [](const PersonClipVertex& v) { return v.clip.z(); });               // near: z >= 0
    polygon = clip_polygon(polygon, [](const PersonClipVertex& v) { return v.clip.w() - v.clip.z(); });  // far: z <= w
    if (polygon.size() < 3) continue;

    std::vector<Eigen::Vector3d> screen;  // x, y in pixels, z in [0, 1]
    for (const PersonClipVertex& v : polygon) {
      const Eigen::Vector3d ndc = v.clip.head<3>() / v.clip.w();
      screen.emplace_back((ndc.x() + 1) * 0.5 * width, (ndc.y() + 1) * 0.5 * height, ndc.z());
    }
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      const size_t ids[3] = {0, k, k + 1};
      const Eigen::Vector2d a = screen[ids[0]].head<2>(), b = screen[ids[1]].head<2>(), c = screen[ids[2]].head<2>();
      // Degenerate triangles: Vulkan draws nothing.
      for_each_pixel_near_triangle(a, b, c, width, height, [&](int x, int y, const Eigen::Vector2d& p, double w0,
                                                                 double w1, double w2) {
          if (distance_to_segment(p, a, b) <= 1.0 || distance_to_segment(p, b, c) <= 1.0 ||
              distance_to_segment(p, c, a) <= 1.0)
            out.near_edge.at(uint32_t(x), uint32_t(y)) = 1.0f;
          const auto weights = depth_tested_weights(
              {w0, w1, w2}, {screen[ids[0]].z(), screen[ids[1]].z(), screen[ids[2]].z()},
              {polygon[ids[0]].clip.w(), polygon[ids[1]].clip.w(), polygon[ids[2]].clip.w()},
              depth_buffer[size_t(y) * width + x]);
          if (!weights) return;
          auto interpolate = [&](auto get) {
            return (*weights)[0] * get(polygon[ids[0]]) + (*weights)[1] * get(polygon[ids[1]]) +
                   (*weights)[2] * get(polygon[ids[2]]);
          };
          std::array<double, 13> at{};
          for (int i = 0; i < 13; ++i) at[i] = interpolate([i](const PersonClipVertex& v) { return v.attributes[i]; });
          Eigen::Vector3d normal(at[3], at[4], at[5]);
          const Eigen::Vector3d light(kLight[0], kLight[1], kLight[2]);
          const Eigen::Vector3d unit = normal.squaredNorm() > 1e-12 ? normal.normalized() : light;
          const double shade = 0.35 + 0.65 * std::abs(unit.dot(light));
          const double period = at[12];
          const bool stripe = period > 0 && at[1] / period - std::floor(at[1] / period) >= 0.5;
          Eigen::Vector4f face(1, 1, 1, 0);
          if (period < 0 && face_texture) face = sample_bilinear(*face_texture, float(at[9]), float(at[10]));
          const double face_weight = face[3] * std::clamp(at[11], 0.0, 1.0);
          for (int channel = 0; channel < 3; ++channel) {
            double albedo = stripe ? at[9 + channel] : at[6 + channel];
            if (period < 0) albedo = at[6 + channel] * (1 - face_weight + face_weight * face[channel]);
            out.color.at(uint32_t(x), uint32_t(y), uint32_t(channel)) =
                float(std::round(std::clamp(albedo * shade, 0.0, 1.0) * 255.0) / 255.0);
          }
          out.color.at(uint32_t(x), uint32_t(y), 3) = 1.0f;
          out.depth_m.at(uint32_t(x), uint32_t(y)) = float(interpolate([](const PersonClipVertex& v) { return v.camera_z; }));
          out.part.at(uint32_t(x), uint32_t(y)) = part;
        });
    }
  }
  return out;
}

}  // namespace rt::passes
