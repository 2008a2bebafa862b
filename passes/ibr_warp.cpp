#include "passes/ibr_warp.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ibr_warp.comp.h"

namespace rt::passes {
namespace {

void require_bands(const vk::Image& atlas, uint32_t width, uint32_t band_height, uint32_t views, const char* what) {
  if (atlas.width() != width || atlas.height() != band_height * views)
    throw std::invalid_argument(std::string("ibr_warp: '") + atlas.name() + "' is not a " + what + " atlas of " +
                                std::to_string(views) + " bands of " + std::to_string(width) + "x" +
                                std::to_string(band_height));
}

}  // namespace

const WarpSettings& checked_warp_settings(const WarpSettings& s) {
  if (!s.visibility.valid() || !(s.feather_px > 0.0f))
    throw std::invalid_argument("warping: visibility tolerances must be >= 0 and feather_px > 0");
  return s;
}

IbrWarpPass::IbrWarpPass(vk::Context& context, const WarpSettings& settings)
    : kernel_(context, "ibr_warp", ibr_warp_comp_spirv,
              {{"visibility_tolerance_m", checked_warp_settings(settings).visibility.metres},
               {"visibility_tolerance_rel", settings.visibility.relative},
               {"feather_px", settings.feather_px}}) {}

void IbrWarpPass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& color,
                         vk::Image& points, vk::Image& warped, vk::Image& features, uint32_t view_count) const {
  if (view_count == 0 || color.height() % view_count != 0 || points.height() % view_count != 0)
    throw std::invalid_argument("ibr_warp: the color and points atlases must hold " + std::to_string(view_count) + " bands");
  require_bands(warped, fused_depth.width(), fused_depth.height(), view_count, "warped color");
  require_bands(features, fused_depth.width(), fused_depth.height(), view_count, "feature");
  graph.add_compute_pass({
      .name = "ibr_warp",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth}, {"color", &color}, {"points", &points}, {"warped", &warped},
                   {"features", &features}, {"IbrSceneTable", &scene.buffer()}},
      .threads = {fused_depth.width(), fused_depth.height(), view_count},
  });
}

double WarpWork::flops() const {
  // Per surface pixel: its target-camera point (two subtractions, divisions and multiplications)
  // and that point in the site frame (three rows of three multiply-adds).
  constexpr double kPerSurfacePixel = 6 + 18;
  // Per sample: the point in the view's camera frame.
  constexpr double kPerSample = 18;
  // In front: two lens projections (the perspective division, r^2, the two radial polynomials
  // and their quotient, the tangential terms, the pinhole) and the image bounds.
  constexpr double kPerInFront = 2 * (2 + 3 + 6 + 6 + 1 + 20 + 4) + 4;
  // Inside: the nearest depth texel and the tolerance test.
  constexpr double kPerInside = 5;
  // Seen: the two rays, their dot product, lengths and cosine, the arc cosine, the resolution
  // penalty, the border and feather, and the bilinear colour (three lerps of rgb, the unorm scale).
  constexpr double kPerSeen = 6 + 5 + 12 + 2 + 1 + 1 + 7 + 29 + 12;
  return kPerSurfacePixel * double(surface_pixels) + kPerSample * double(samples) + kPerInFront * double(in_front) +
         kPerInside * double(inside) + kPerSeen * double(seen);
}

WarpedViews ibr_warp_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& color,
                               const HostImage& points, const WarpSettings& s, WarpWork* work) {
  WarpWork counted;
  const uint32_t width = fused_depth.width, height = fused_depth.height;
  WarpedViews out{HostImage(width, height * table.camera_count, PixelFormat::RGBA32F),
                  HostImage(width, height * table.camera_count, PixelFormat::RGBA32F)};
  const shader_abi::IbrTarget& target = table.target;
  const Float3 eye = transform_point(target.site_from_camera, {0, 0, 0});
  for (uint32_t view = 0; view < table.camera_count; ++view) {
    const shader_abi::IbrCamera& camera = table.cameras[view];
    const Float2 color_size{camera.color.tangential[2], camera.color.tangential[3]};
    const Float2 depth_size{camera.depth.tangential[2], camera.depth.tangential[3]};
    const Float3 centre = transform_point(camera.site_from_camera, {0, 0, 0});
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const float z = fused_depth.at(x, y);
        if (!(z > 0.0f)) continue;
        ++counted.samples;
        const Float3 target_point{(float(x) - target.pinhole[2]) / target.pinhole[0] * z,
                                  (float(y) - target.pinhole[3]) / target.pinhole[1] * z, z};
        const Float3 site = transform_point(target.site_from_camera, target_point);
        const Float3 q = transform_point(camera.camera_from_site, site);
        if (!(q.z > 1e-4f)) continue;
        ++counted.in_front;
        const Float2 color_pixel = lens_project(camera.color, q);
        const Float2 depth_pixel = lens_project(camera.depth, q);
        if (!inside_image(color_pixel, color_size, 0.0f) || !inside_image(depth_pixel, depth_size, 0.0f)) continue;
        ++counted.inside;
        if (!view_sees(points, view, uint32_t(depth_size.y), depth_pixel, q.z, s.visibility)) continue;
        ++counted.seen;
        const Float3 to_eye{site.x - eye.x, site.y - eye.y, site.z - eye.z};
        const Float3 to_camera{site.x - centre.x, site.y - centre.y, site.z - centre.z};
        const float cosine = (to_eye.x * to_camera.x + to_eye.y * to_camera.y + to_eye.z * to_camera.z) /
                             std::max(length(to_eye) * length(to_camera), 1e-12f);
        const float border = std::min(std::min(color_pixel.x + 0.5f, color_size.x - 0.5f - color_pixel.x),
                                      std::min(color_pixel.y + 0.5f, color_size.y - 0.5f - color_pixel.y));
        const auto rgb = bilinear_rgb(color, color_pixel, view * uint32_t(color_size.y), uint32_t(color_size.x),
                                      uint32_t(color_size.y));
        const uint32_t row = y + view * height;
        float* warped = &out.warped.texels[out.warped.index(x, row)];
        warped[0] = rgb[0], warped[1] = rgb[1], warped[2] = rgb[2], warped[3] = 1.0f;
        float* features = &out.features.texels[out.features.index(x, row)];
        features[0] = std::acos(std::clamp(cosine, -1.0f, 1.0f));
        features[1] = std::max(0.0f, length(to_camera) - length(to_eye));
        features[2] = std::clamp(border / s.feather_px, 1e-3f, 1.0f);
        features[3] = 1.0f;
      }
  }
  if (work) {
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        if (!(fused_depth.at(x, y) > 0.0f)) continue;
        ++counted.surface_pixels;
        bool seen = false;
        for (uint32_t view = 0; view < table.camera_count; ++view)
          seen = seen || out.features.at(x, y + view * height, 3) > 0.0f;
        if (seen) ++counted.covered;
      }
    *work = counted;
  }
  return out;
}

}  // namespace rt::passes
