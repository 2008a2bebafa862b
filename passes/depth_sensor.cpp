#include "passes/depth_sensor.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "depth_sensor.comp.h"
#include "passes/common/random_reference.h"
#include "shared/config.h"

namespace rt::passes {
namespace {

const DepthSensorModel& checked(const DepthSensorModel& model) {
  check_depth_sensor_model(model);
  return model;
}

}  // namespace

void check_depth_sensor_model(const DepthSensorModel& m) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("depth sensor: " + what); };
  const float values[] = {m.range_min_m, m.range_max_m, m.noise_sigma_at_1m_m, m.skin_bias_m, m.flying_edge_m,
                          m.flying_probability};
  for (float value : values)
    if (!std::isfinite(value)) fail("every parameter must be finite");
  if (!(m.range_min_m > 0.0f) || !(m.range_max_m > m.range_min_m)) fail("needs 0 < range_min_m < range_max_m");
  if (m.range_max_m > 65.535f) fail("range_max_m above 65.535 m does not fit 16-bit millimetres");
  if (m.noise_sigma_at_1m_m < 0.0f) fail("noise_sigma_at_1m_m must be >= 0");
  if (m.flying_edge_m < 0.0f) fail("flying_edge_m must be >= 0");
  if (m.flying_probability < 0.0f || m.flying_probability > 1.0f) fail("flying_probability must be in [0, 1]");
}

DepthSensorPass::DepthSensorPass(vk::Context& context, const DepthSensorModel& model)
    : kernel_(context, "depth_sensor", depth_sensor_comp_spirv,
              {{"range_min_m", checked(model).range_min_m},
               {"range_max_m", model.range_max_m},
               {"noise_sigma_at_1m_m", model.noise_sigma_at_1m_m},
               {"skin_bias_m", model.skin_bias_m},
               {"flying_edge_m", model.flying_edge_m},
               {"flying_probability", model.flying_probability},
               {"shift_x", int32_t(model.shift_x)},
               {"shift_y", int32_t(model.shift_y)}}) {}

void DepthSensorPass::add_to(vk::FrameGraph& graph, vk::Image& depth_m, vk::Image& part, vk::Image& depth_mm,
                             std::function<uint32_t()> seed, const std::string& pass_name) const {
  if (depth_m.width() != depth_mm.width() || depth_m.height() != depth_mm.height() || part.width() != depth_m.width() ||
      part.height() != depth_m.height())
    throw std::invalid_argument(pass_name + ": depth, part and output images differ in size");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"depth_m", &depth_m}, {"part", &part}, {"depth_mm", &depth_mm}},
      .threads = {depth_mm.width(), depth_mm.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::DepthSensorParams>(
          [seed = std::move(seed)] { return shader_abi::DepthSensorParams{seed()}; }),
  });
}

HostImage depth_sensor_reference(const HostImage& depth_m, const HostImage& part, const DepthSensorModel& model,
                                 uint32_t seed) {
  check_depth_sensor_model(model);
  const int width = int(depth_m.width), height = int(depth_m.height);
  auto surface_at = [&](int x, int y) -> float {
    if (x < 0 || y < 0 || x >= width || y >= height) return 0.0f;
    const float z = depth_m.at(uint32_t(x), uint32_t(y));
    return std::isfinite(z) && z > 0.0f ? z : 0.0f;
  };
  HostImage out(depth_m.width, depth_m.height, PixelFormat::R16U);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int sx = x - model.shift_x, sy = y - model.shift_y;
      float z = surface_at(sx, sy);
      if (z > 0.0f && model.flying_edge_m > 0.0f) {
        float farthest = z;
        bool edge = false;
        const int offsets[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
        for (const auto& offset : offsets) {
          const float neighbour = surface_at(sx + offset[0], sy + offset[1]);
          if (neighbour == 0.0f || std::abs(neighbour - z) > model.flying_edge_m) edge = true;
          farthest = std::max(farthest, neighbour);
        }
        if (edge) {
          const float roll = uniform01(pixel_hash(x, y, seed, 3u));
          if (roll < 0.5f * model.flying_probability) z = 0.0f;
          else if (roll < model.flying_probability) {
            const float t = uniform01(pixel_hash(x, y, seed, 4u));
            z = z + (farthest - z) * t;
          }
        }
      }
      const bool inside = sx >= 0 && sy >= 0 && sx < width && sy < height;
      if (z > 0.0f && model.skin_bias_m != 0.0f && inside && part.at(uint32_t(sx), uint32_t(sy)) == float(RT_PART_HAND))
        z += model.skin_bias_m;
      if (z > 0.0f && model.noise_sigma_at_1m_m > 0.0f) z += model.noise_sigma_at_1m_m * z * z * normal01(x, y, seed);
      float millimetres = 0.0f;
      if (z >= model.range_min_m && z <= model.range_max_m)
        millimetres = std::clamp(std::floor(z * 1000.0f + 0.5f), 1.0f, 65535.0f);
      out.at(uint32_t(x), uint32_t(y)) = millimetres;
    }
  return out;
}

}  // namespace rt::passes
