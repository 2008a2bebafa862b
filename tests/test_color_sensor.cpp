// color_sensor pass: GPU against the C++ reference; 8-bit output, tolerance one step (1/255).
#include <limits>

#include "passes/color_sensor.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

constexpr double kOneStep = 1.0 / 255.0 + 1e-6;

HostImage quantised(HostImage image) {
  for (float& v : image.texels) v = std::round(v * 255.0f) / 255.0f;
  return image;
}

HostImage run_gpu_color_sensor(const HostImage& input, const passes::ColorSensorModel& model) {
  const passes::ColorSensorPass pass(test::gpu(), model);
  test::PassHarness gpu("color_sensor");
  pass.add_to(gpu.graph(), gpu.input("rendered", input),
              gpu.output("sensed", input.width, input.height, PixelFormat::RGBA8));
  return gpu.run().image("sensed");
}

}  // namespace

TEST_CASE("color_sensor: off is the identity; gain and balance as the reference", "[color_sensor][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(41);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const HostImage input = quantised(test::random_image(rng, width, height, PixelFormat::RGBA8));
    RT_REQUIRE_MATCHES(run_gpu_color_sensor(input, {}), input, 0.0, 0.0);
    const passes::ColorSensorModel warm{1.3f, 1.1f, 1.0f, 0.8f};
    RT_REQUIRE_MATCHES(run_gpu_color_sensor(input, warm), passes::color_sensor_reference(input, warm), kOneStep, 0.0);
  }
}

TEST_CASE("color_sensor hard cases: black, saturated, zero gain, bad models", "[color_sensor][gpu]") {
  test::NoValidationErrors no_errors;
  const passes::ColorSensorModel bright{4.0f, 1.0f, 1.0f, 1.0f};
  const HostImage white(7, 5, PixelFormat::RGBA8, 1.0f), black(7, 5, PixelFormat::RGBA8, 0.0f);
  RT_REQUIRE_MATCHES(run_gpu_color_sensor(white, bright), white, 0.0, 0.0);  // clipped, not wrapped
  RT_REQUIRE_MATCHES(run_gpu_color_sensor(black, bright), black, 0.0, 0.0);
  HostImage expected_dark(7, 5, PixelFormat::RGBA8, 0.0f);
  for (size_t i = 3; i < expected_dark.texels.size(); i += 4) expected_dark.texels[i] = 1.0f;
  RT_REQUIRE_MATCHES(run_gpu_color_sensor(white, {0.0f, 1.0f, 1.0f, 1.0f}), expected_dark, 0.0, 0.0);
  CHECK_THROWS_WITH(passes::check_color_sensor_model({-1.0f, 1.0f, 1.0f, 1.0f}), Catch::Contains("gain"));
  CHECK_THROWS(passes::check_color_sensor_model({1.0f, std::numeric_limits<float>::quiet_NaN(), 1.0f, 1.0f}));
}
