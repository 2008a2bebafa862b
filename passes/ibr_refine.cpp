#include "passes/ibr_refine.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ibr_refine.comp.h"

namespace rt::passes {
namespace {

const RefineSettings& check(const RefineSettings& s, VisibilityTolerance visibility) {
  if (s.hypotheses < 1 || s.hypotheses > 64 || !(s.step_m > 0.0f) || !std::isfinite(s.step_m))
    throw std::invalid_argument("depth refinement: hypotheses must be 1..64 and step_m a positive number of metres");
  if (!visibility.valid()) throw std::invalid_argument("depth refinement: visibility tolerances must be >= 0");
  return s;
}

// Color variance across the views that see `site` (inside their color and depth images, their
// own depth agreeing); -1 with fewer than two.
float disagreement(const IbrSceneTable& table, const HostImage& color, const HostImage& points, Float3 site,
                   VisibilityTolerance visibility) {
  std::array<float, 3> sum{}, squares{};
  int seen = 0;
  for (uint32_t v = 0; v < table.camera_count; ++v) {
    const shader_abi::IbrCamera& camera = table.cameras[v];
    const Float3 q = transform_point(camera.camera_from_site, site);
    if (!(q.z > 1e-4f)) continue;
    const Float2 at = lens_project(camera.color, q);
    const Float2 size{camera.color.tangential[2], camera.color.tangential[3]};
    const Float2 depth_size{camera.depth.tangential[2], camera.depth.tangential[3]};
    const Float2 depth_pixel = lens_project(camera.depth, q);
    if (!inside_image(at, size, 0.0f) || !inside_image(depth_pixel, depth_size, 0.0f)) continue;
    if (!view_sees(points, v, uint32_t(depth_size.y), depth_pixel, q.z, visibility)) continue;
    const auto c = bilinear_rgb(color, at, v * uint32_t(size.y), uint32_t(size.x), uint32_t(size.y));
    for (size_t i = 0; i < 3; ++i) sum[i] += c[i], squares[i] += c[i] * c[i];
    ++seen;
  }
  if (seen < 2) return -1.0f;
  float variance = 0.0f;
  for (size_t i = 0; i < 3; ++i) {
    const float mean = sum[i] / float(seen);
    variance += std::max(squares[i] / float(seen) - mean * mean, 0.0f);
  }
  return variance;
}

}  // namespace

IbrRefinePass::IbrRefinePass(vk::Context& context, const RefineSettings& settings, VisibilityTolerance visibility)
    : kernel_(context, "ibr_refine", ibr_refine_comp_spirv,
              {{"hypotheses", int32_t(check(settings, visibility).hypotheses)},
               {"step_m", settings.step_m},
               {"visibility_tolerance_m", visibility.metres},
               {"visibility_tolerance_rel", visibility.relative}}) {}

void IbrRefinePass::add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& color,
                           vk::Image& points, vk::Image& refined_depth, uint32_t view_count) const {
  if (refined_depth.width() != fused_depth.width() || refined_depth.height() != fused_depth.height())
    throw std::invalid_argument("ibr_refine: refined and fused depth differ in size");
  if (view_count == 0 || color.height() % view_count != 0 || points.height() % view_count != 0)
    throw std::invalid_argument("ibr_refine: the color and points atlases must hold " + std::to_string(view_count) +
                                " bands");
  graph.add_compute_pass({
      .name = "ibr_refine",
      .kernel = &kernel_,
      .bindings = {{"fused_depth", &fused_depth},
                   {"color", &color},
                   {"points", &points},
                   {"refined_depth", &refined_depth},
                   {"IbrSceneTable", &scene.buffer()}},
      .threads = {fused_depth.width(), fused_depth.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::IbrBlendParams>(
          [view_count] { return shader_abi::IbrBlendParams{view_count}; }),
  });
}

HostImage ibr_refine_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& color,
                               const HostImage& points, const RefineSettings& s, VisibilityTolerance visibility) {
  HostImage refined = fused_depth;
  const shader_abi::IbrTarget& target = table.target;
  for (uint32_t y = 0; y < fused_depth.height; ++y)
    for (uint32_t x = 0; x < fused_depth.width; ++x) {
      const float z = fused_depth.at(x, y);
      if (!(z > 0.0f)) continue;
      const float rx = (float(x) - target.pinhole[2]) / target.pinhole[0];
      const float ry = (float(y) - target.pinhole[3]) / target.pinhole[1];
      float best_score = 1e30f, best_offset = 1e30f, best_z = z;
      for (int h = 0; h < s.hypotheses; ++h) {
        const float offset = (float(h) - 0.5f * float(s.hypotheses - 1)) * s.step_m;
        const float candidate = z + offset;
        if (candidate <= 1e-3f) continue;
        const float score =
            disagreement(table, color, points,
                         transform_point(target.site_from_camera, {rx * candidate, ry * candidate, candidate}), visibility);
        if (score < 0.0f) continue;
        if (score < best_score || (score == best_score && std::abs(offset) < best_offset)) {
          best_score = score;
          best_offset = std::abs(offset);
          best_z = candidate;
        }
      }
      refined.at(x, y) = best_z;
    }
  return refined;
}

}  // namespace rt::passes
