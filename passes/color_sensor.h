#pragma once
// Pass: a color camera's response to the rendered color: gain and white balance, clipped.
//   in: rendered rgba8   out: sensed rgba8
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct ColorSensorModel {
  float gain = 1.0f;
  float balance_r = 1.0f, balance_g = 1.0f, balance_b = 1.0f;
};

void check_color_sensor_model(const ColorSensorModel& model);  // finite, >= 0

class ColorSensorPass {
 public:
  ColorSensorPass(vk::Context& context, const ColorSensorModel& model);
  void add_to(vk::FrameGraph& graph, vk::Image& rendered, vk::Image& sensed,
              const std::string& pass_name = "color_sensor") const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage color_sensor_reference(const HostImage& rendered, const ColorSensorModel& model);

}  // namespace rt::passes
