#include "passes/ibr_carve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ibr_carve.comp.h"

namespace rt::passes {
namespace {

const CarveSettings& check(const CarveSettings& s, VisibilityTolerance visibility) {
  if (!(s.probe_texels >= 0.0f && s.probe_texels < 0.5f) || s.march_steps < 0 || s.march_steps > 16)
    throw std::invalid_argument("see-through carving: probe_texels must be in [0, 0.5) and march_steps 0..16");
  if (!visibility.valid()) throw std::invalid_argument("see-through carving: visibility tolerances must be >= 0");
  return s;
}

// Mirrors shaders/ibr_carve.comp line by line.
struct Carver {
  const IbrSceneTable& table;
  const HostImage& points;
  const CarveSettings& s;
  VisibilityTolerance visibility;

  const float* own_point(uint32_t view, Float2 depth_pixel, int width, int height) const {
    const int x = std::clamp(int(std::floor(depth_pixel.x + 0.5f)), 0, width - 1);
    const int y = std::clamp(int(std::floor(depth_pixel.y + 0.5f)), 0, height - 1);
    return &points.texels[points.index(uint32_t(x), uint32_t(y) + view * uint32_t(height))];
  }
  bool farther(float own, float z) const {
    return own > 0.0f && own > z + visibility.metres + visibility.relative * own;
  }
  Float3 ray_point(Float2 ray, float z) const {
    return transform_point(table.target.site_from_camera, {ray.x * z, ray.y * z, z});
  }
  // The target depth where the ray meets the view's depth surface, from `z`; the last estimate if
  // the ray leaves the view's image or valid depth on the way.
  float march_onto_view(uint32_t view, Float2 ray, float z, int width, int height) const {
    const auto& camera_from_site = table.cameras[view].camera_from_site;
    const float at_eye = transform_point(camera_from_site, ray_point(ray, 0.0f)).z;
    const float per_metre = transform_point(camera_from_site, ray_point(ray, 1.0f)).z - at_eye;
    if (!(std::abs(per_metre) > 1e-6f)) return z;
    for (int step = 0; step < s.march_steps; ++step) {
      const Float3 q = transform_point(camera_from_site, ray_point(ray, z));
      if (q.z <= 1e-4f) break;
      const Float2 depth_pixel = lens_project(table.cameras[view].depth, q);
      if (!inside_image(depth_pixel, {float(width), float(height)}, 0.0f)) break;
      const float own = own_point(view, depth_pixel, width, height)[3];
      if (!(own > 0.0f)) break;
      z = (own - at_eye) / per_metre;
    }
    return z;
  }

  float carve(Float2 ray, float z) const {
    const Float3 site = ray_point(ray, z);
    float behind = 0.0f;
    for (uint32_t v = 0; v < table.camera_count; ++v) {
      const shader_abi::IbrCamera& camera = table.cameras[v];
      const Float3 q = transform_point(camera.camera_from_site, site);
      if (q.z <= 1e-4f) continue;
      const int width = int(camera.depth.tangential[2]), height = int(camera.depth.tangential[3]);
      const Float2 depth_pixel = lens_project(camera.depth, q);
      if (!inside_image(depth_pixel, {float(width), float(height)}, 0.0f)) continue;
      bool sees_through = true;
      for (int corner = 0; corner < 4; ++corner) {
        const Float2 probe{depth_pixel.x + ((corner & 1) == 0 ? -s.probe_texels : s.probe_texels),
                           depth_pixel.y + ((corner & 2) == 0 ? -s.probe_texels : s.probe_texels)};
        if (!farther(own_point(v, probe, width, height)[3], q.z)) sees_through = false;
      }
      if (!sees_through) continue;
      const float* own = own_point(v, depth_pixel, width, height);
      const float start = transform_point(table.target.camera_from_site, {own[0], own[1], own[2]}).z;
      const float surface = march_onto_view(v, ray, start, width, height);
      if (surface > z && (behind == 0.0f || surface < behind)) behind = surface;
    }
    if (!(behind > z)) return z;
    const Float3 behind_site = ray_point(ray, behind);
    for (uint32_t v = 0; v < table.camera_count; ++v) {
      const shader_abi::IbrCamera& camera = table.cameras[v];
      const Float3 q = transform_point(camera.camera_from_site, behind_site);
      if (q.z <= 1e-4f) continue;
      const Float2 depth_size{camera.depth.tangential[2], camera.depth.tangential[3]};
      const Float2 depth_pixel = lens_project(camera.depth, q);
      if (!inside_image(depth_pixel, depth_size, 0.0f) ||
          !inside_image(lens_project(camera.color, q), {camera.color.tangential[2], camera.color.tangential[3]}, 0.0f))
        continue;
      if (view_sees(points, v, uint32_t(depth_size.y), depth_pixel, q.z, visibility)) return behind;
    }
    return z;
  }
};

}  // namespace

IbrCarvePass::IbrCarvePass(vk::Context& context, const CarveSettings& settings, VisibilityTolerance visibility)
    : kernel_(context, "ibr_carve", ibr_carve_comp_spirv,
              {{"visibility_tolerance_m", visibility.metres},
               {"visibility_tolerance_rel", visibility.relative},
               {"probe_texels", check(settings, visibility).probe_texels},
               {"march_steps", int32_t(settings.march_steps)}}) {}

void IbrCarvePass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& points,
                          vk::Image& carved_depth, uint32_t view_count) const {
  if (carved_depth.width() != fused_depth.width() || carved_depth.height() != fused_depth.height())
    throw std::invalid_argument("ibr_carve: carved and fused depth differ in size");
  if (view_count == 0 || points.height() % view_count != 0)
    throw std::invalid_argument("ibr_carve: the points atlas must hold " + std::to_string(view_count) + " bands");
  graph.add_compute_pass({
      .name = "ibr_carve",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth},
                   {"points", &points},
                   {"carved_depth", &carved_depth},
                   {"IbrSceneTable", &scene.buffer()}},
      .threads = {fused_depth.width(), fused_depth.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::IbrBlendParams>(
          [view_count] { return shader_abi::IbrBlendParams{view_count}; }),
  });
}

HostImage ibr_carve_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& points,
                              const CarveSettings& s, VisibilityTolerance visibility) {
  check(s, visibility);
  const Carver carver{table, points, s, visibility};
  HostImage carved = fused_depth;
  const shader_abi::IbrTarget& target = table.target;
  for (uint32_t y = 0; y < fused_depth.height; ++y)
    for (uint32_t x = 0; x < fused_depth.width; ++x) {
      const float z = fused_depth.at(x, y);
      carved.at(x, y) = 0.0f;  // nothing there, also for a NaN, infinite or negative depth
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      const Float2 ray{(float(x) - target.pinhole[2]) / target.pinhole[0], (float(y) - target.pinhole[3]) / target.pinhole[1]};
      carved.at(x, y) = carver.carve(ray, z);
    }
  return carved;
}

}  // namespace rt::passes
