#include "passes/ibr_foreground.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "ibr_foreground.comp.h"

namespace rt::passes {
namespace {

const ForegroundSettings& check(const ForegroundSettings& s) {
  if (!(s.volume_min.array() < s.volume_max.array()).all() || !s.volume_min.allFinite() || !s.volume_max.allFinite())
    throw std::invalid_argument("background removal: the user's volume needs finite min < max on every axis");
  if (s.min_support < 0 || s.min_support > 8 || !(s.edge_tolerance_m > 0.0f))
    throw std::invalid_argument("background removal: min_support must be 0..8 and edge_tolerance_m positive");
  return s;
}

shader_abi::IbrForegroundParams params_of(const ForegroundSettings& s) {
  return {.volume_min = {s.volume_min.x(), s.volume_min.y(), s.volume_min.z(), 0.0f},
          .volume_max = {s.volume_max.x(), s.volume_max.y(), s.volume_max.z(), 0.0f}};
}

}  // namespace

IbrForegroundPass::IbrForegroundPass(vk::Context& context, const ForegroundSettings& settings)
    : settings_(check(settings)),
      kernel_(context, "ibr_foreground", ibr_foreground_comp_spirv,
              {{"min_support", int32_t(settings.min_support)}, {"edge_tolerance_m", settings.edge_tolerance_m}}) {}

void IbrForegroundPass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& depth_mm,
                               vk::Image& depth_rays, vk::Image& points, IbrTiles& point_tiles,
                               uint32_t view_count) const {
  if (view_count == 0 || depth_mm.height() % view_count != 0)
    throw std::invalid_argument("ibr_foreground: the depth atlas does not hold " + std::to_string(view_count) + " bands");
  for (const vk::Image* image : {&depth_rays, &points})
    if (image->width() != depth_mm.width() || image->height() != depth_mm.height())
      throw std::invalid_argument("ibr_foreground: '" + image->name() + "' differs in size from the depth atlas");
  if (point_tiles.layers() != view_count || !point_tiles.lists_bands_of(depth_mm))
    throw std::invalid_argument("ibr_foreground: the tile list is not one of " + std::to_string(view_count) +
                                " views of the depth atlas's bands");
  add_tile_reset(graph, "ibr_point_tiles_reset", point_tiles);
  graph.add_compute_pass({
      .name = "ibr_foreground",
      .kernel = &kernel_,
      .bindings = {{"depth_mm", &depth_mm},
                   {"depth_rays", &depth_rays},
                   {"points", &points},
                   {"IbrSceneTable", &scene.buffer()},
                   {"TileDispatch", &point_tiles.dispatch()},
                   {"Tiles", &point_tiles.tiles()}},
      .threads = {depth_mm.width(), depth_mm.height() / view_count, view_count},
      .push_constants = vk::push_constants_from<shader_abi::IbrForegroundParams>(
          [params = params_of(settings_)] { return params; }),
  });
}

HostImage ibr_foreground_reference(const IbrSceneTable& table, const HostImage& depth_mm, const HostImage& depth_rays,
                                   const ForegroundSettings& s) {
  HostImage points(depth_mm.width, depth_mm.height, PixelFormat::RGBA32F);
  for (uint32_t view = 0; view < table.camera_count; ++view) {
    const shader_abi::IbrCamera& camera = table.cameras[view];
    const int width = int(camera.depth.tangential[2]), height = int(camera.depth.tangential[3]);
    const uint32_t band = view * uint32_t(height);
    // The camera's position: the last column of site_from_camera (column-major).
    const Float3 origin{camera.site_from_camera[12], camera.site_from_camera[13], camera.site_from_camera[14]};
    auto site_point = [&](const float* ray, float z) {
      return Float3{origin.x + z * ray[0], origin.y + z * ray[1], origin.z + z * ray[2]};
    };
    auto volume_depth = [&](int x, int y) {
      if (x < 0 || y < 0 || x >= width || y >= height) return 0.0f;
      const float millimetres = depth_mm.at(uint32_t(x), uint32_t(y) + band);
      const float* ray = &depth_rays.texels[depth_rays.index(uint32_t(x), uint32_t(y) + band)];
      if (millimetres == 0.0f || ray[3] == 0.0f) return 0.0f;
      const float z = millimetres * 0.001f;
      const Float3 site = site_point(ray, z);
      const bool inside = site.x >= s.volume_min.x() && site.y >= s.volume_min.y() && site.z >= s.volume_min.z() &&
                          site.x <= s.volume_max.x() && site.y <= s.volume_max.y() && site.z <= s.volume_max.z();
      return inside ? z : 0.0f;
    };
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float z = volume_depth(x, y);
        if (z <= 0.0f) continue;
        int support = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if (dx == 0 && dy == 0) continue;
            const float neighbour = volume_depth(x + dx, y + dy);
            if (neighbour > 0.0f && std::abs(neighbour - z) <= s.edge_tolerance_m) ++support;
          }
        if (support < s.min_support) continue;
        const float* ray = &depth_rays.texels[depth_rays.index(uint32_t(x), uint32_t(y) + band)];
        const Float3 site = site_point(ray, z);
        float* out = &points.texels[points.index(uint32_t(x), uint32_t(y) + band)];
        out[0] = site.x;
        out[1] = site.y;
        out[2] = site.z;
        out[3] = z;
      }
  }
  return points;
}

}  // namespace rt::passes
