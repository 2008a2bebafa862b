#include "passes/color_sensor.h"

#include <cmath>
#include <stdexcept>

#include "color_sensor.comp.h"
#include "passes/common/reference_math.h"

namespace rt::passes {
namespace {

const ColorSensorModel& checked(const ColorSensorModel& model) {
  check_color_sensor_model(model);
  return model;
}

}  // namespace

void check_color_sensor_model(const ColorSensorModel& m) {
  for (float value : {m.gain, m.balance_r, m.balance_g, m.balance_b})
    if (!std::isfinite(value) || value < 0.0f)
      throw std::invalid_argument("color sensor: gain and white balance must be finite and >= 0");
}

ColorSensorPass::ColorSensorPass(vk::Context& context, const ColorSensorModel& model)
    : kernel_(context, "color_sensor", color_sensor_comp_spirv,
              {{"gain", checked(model).gain},
               {"balance_r", model.balance_r},
               {"balance_g", model.balance_g},
               {"balance_b", model.balance_b}}) {}

void ColorSensorPass::add_to(vk::FrameGraph& graph, vk::Image& rendered, vk::Image& sensed,
                             const std::string& pass_name) const {
  if (rendered.width() != sensed.width() || rendered.height() != sensed.height())
    throw std::invalid_argument(pass_name + ": rendered and sensed images differ in size");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"rendered", &rendered}, {"sensed", &sensed}},
      .threads = {sensed.width(), sensed.height(), 1},
  });
}

HostImage color_sensor_reference(const HostImage& rendered, const ColorSensorModel& model) {
  HostImage sensed(rendered.width, rendered.height, PixelFormat::RGBA8);
  const float balance[3] = {model.balance_r, model.balance_g, model.balance_b};
  for (uint32_t y = 0; y < rendered.height; ++y)
    for (uint32_t x = 0; x < rendered.width; ++x) {
      for (uint32_t c = 0; c < 3; ++c)
        sensed.at(x, y, c) = std::round(unit_or_zero(rendered.at(x, y, c) * model.gain * balance[c]) * 255.0f) / 255.0f;
      sensed.at(x, y, 3) = rendered.at(x, y, 3);
    }
  return sensed;
}

}  // namespace rt::passes
