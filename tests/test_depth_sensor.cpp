// depth_sensor pass: GPU against the C++ reference, and each effect's statistics against its
// parameters. Tolerances: effects off, exact millimetres; effects on, within 1 mm (the GPU's
// log/cos differ from the C library's in the last bits), validity identical on at least
// 99.95% of pixels (a noisy depth that lands within float rounding of a range end may flip).
#include <cmath>
#include <limits>
#include <numeric>

#include "passes/depth_sensor.h"
#include "shared/config.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::DepthSensorModel;

namespace {

HostImage run_gpu_depth_sensor(const HostImage& depth, const HostImage& part, const DepthSensorModel& model, uint32_t seed) {
  const passes::DepthSensorPass pass(test::gpu(), model);
  test::PassHarness gpu("depth_sensor");
  pass.add_to(gpu.graph(), gpu.input("depth m", depth), gpu.input("part", part),
              gpu.output("depth mm", depth.width, depth.height, PixelFormat::R16U), [seed] { return seed; });
  return gpu.run().image("depth mm");
}

// A scene-like depth image: a background at 2.5 m, a body at 1.2 m, a hand at 0.6 m, holes.
struct DepthScene {
  HostImage depth, part;
};
DepthScene scene_depth_sensor(std::mt19937& rng, uint32_t w, uint32_t h) {
  DepthScene s{HostImage(w, h, PixelFormat::R32F), HostImage(w, h, PixelFormat::R32F)};
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f), unit(0.0f, 1.0f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const float fx = float(x) / float(w), fy = float(y) / float(h);
      float z = 2.5f + jitter(rng), part = float(RT_PART_NONE);
      if (std::hypot(fx - 0.5f, fy - 0.6f) < 0.3f) z = 1.2f + jitter(rng), part = float(RT_PART_BODY);
      if (std::hypot(fx - 0.7f, fy - 0.4f) < 0.12f) z = 0.6f + jitter(rng), part = float(RT_PART_HAND);
      if (unit(rng) < 0.05f) z = 0.0f;  // nothing there
      s.depth.at(x, y) = z;
      s.part.at(x, y) = part;
    }
  return s;
}

DepthSensorModel every_effect() {
  DepthSensorModel model;
  model.range_min_m = 0.3f;
  model.noise_sigma_at_1m_m = 0.004f;
  model.skin_bias_m = 0.01f;
  model.flying_edge_m = 0.05f;
  model.flying_probability = 0.6f;
  model.shift_x = 2;
  model.shift_y = -1;
  return model;
}

void require_close(const HostImage& gpu, const HostImage& reference, float tolerance_mm, double max_validity_flips) {
  REQUIRE(test::count_non_finite(gpu) == 0);
  size_t flips = 0, far = 0;
  for (size_t i = 0; i < gpu.texels.size(); ++i) {
    const bool gpu_valid = gpu.texels[i] > 0, reference_valid = reference.texels[i] > 0;
    if (gpu_valid != reference_valid) ++flips;
    else if (std::abs(gpu.texels[i] - reference.texels[i]) > tolerance_mm) ++far;
  }
  CHECK(far == 0);
  CHECK(double(flips) <= max_validity_flips * double(gpu.texels.size()));
}

}  // namespace

TEST_CASE("depth_sensor with effects off is the ground truth in millimetres", "[depth_sensor][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(31);
  for (const auto& [width, height] : test::odd_sizes()) {
    INFO(width << "x" << height);
    const DepthScene s = scene_depth_sensor(rng, width, height);
    const HostImage gpu = run_gpu_depth_sensor(s.depth, s.part, {}, 7);
    RT_REQUIRE_MATCHES(gpu, passes::depth_sensor_reference(s.depth, s.part, {}, 7), 0.0, 0.0);
    for (size_t i = 0; i < gpu.texels.size(); ++i) {
      const float z = s.depth.texels[i];
      const float expected = z >= 0.25f && z <= 2.88f ? std::floor(z * 1000.0f + 0.5f) : 0.0f;
      REQUIRE(gpu.texels[i] == expected);
    }
  }
}

TEST_CASE("depth_sensor hard cases: NaN, Inf, negative, range ends, empty", "[depth_sensor][gpu]") {
  test::NoValidationErrors no_errors;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  HostImage depth(9, 1, PixelFormat::R32F);
  depth.texels = {nan, inf, -inf, -1.0f, 0.0f, 0.25f, 2.88f, 0.2499f, 2.8801f};
  const HostImage part(9, 1, PixelFormat::R32F, float(RT_PART_HAND));
  for (const DepthSensorModel& model : {DepthSensorModel{}, every_effect()}) {
    const HostImage gpu = run_gpu_depth_sensor(depth, part, model, 3);
    require_close(gpu, passes::depth_sensor_reference(depth, part, model, 3), 1.0f, 0.0);
  }
  const HostImage gpu = run_gpu_depth_sensor(depth, HostImage(9, 1, PixelFormat::R32F), {}, 3);
  CHECK(gpu.texels == std::vector<float>{0, 0, 0, 0, 0, 250, 2880, 0, 0});
}

TEST_CASE("depth_sensor with every effect on matches the reference", "[depth_sensor][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(32);
  for (const auto& [width, height] : std::vector<std::pair<uint32_t, uint32_t>>{{641, 359}, {33, 17}, {7, 5}}) {
    INFO(width << "x" << height);
    const DepthScene s = scene_depth_sensor(rng, width, height);
    const HostImage gpu = run_gpu_depth_sensor(s.depth, s.part, every_effect(), 11);
    require_close(gpu, passes::depth_sensor_reference(s.depth, s.part, every_effect(), 11), 1.0f, 0.0005);
  }
}

TEST_CASE("depth_sensor effects: measured statistics match their parameters", "[depth_sensor][gpu]") {
  test::NoValidationErrors no_errors;
  const uint32_t w = 640, h = 576;  // the NFOV resolution: plenty of samples
  const HostImage plane(w, h, PixelFormat::R32F, 1.0f);
  const HostImage body(w, h, PixelFormat::R32F, float(RT_PART_BODY));

  SECTION("noise: sigma at 1 m within 10% of the configured value, mean unbiased") {
    DepthSensorModel model;
    model.noise_sigma_at_1m_m = 0.006f;
    const HostImage gpu = run_gpu_depth_sensor(plane, body, model, 5);
    double sum = 0, sum2 = 0;
    for (float mm : gpu.texels) sum += mm / 1000.0, sum2 += (mm / 1000.0) * (mm / 1000.0);
    const double n = double(gpu.texels.size()), mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
    CHECK(mean == Approx(1.0).margin(0.0005));
    CHECK(sigma == Approx(0.006).epsilon(0.10));
    // Quadratic growth: at 2 m the sigma is four times larger.
    const HostImage far = run_gpu_depth_sensor(HostImage(w, h, PixelFormat::R32F, 2.0f), body, model, 6);
    double far_sum = 0, far_sum2 = 0;
    for (float mm : far.texels) far_sum += mm / 1000.0, far_sum2 += (mm / 1000.0) * (mm / 1000.0);
    const double far_mean = far_sum / n;
    CHECK(std::sqrt(far_sum2 / n - far_mean * far_mean) == Approx(0.024).epsilon(0.10));
  }
  SECTION("skin bias: hand pixels read farther by the bias, others not") {
    DepthSensorModel model;
    model.skin_bias_m = 0.01f;
    const HostImage hand(w, h, PixelFormat::R32F, float(RT_PART_HAND));
    CHECK(run_gpu_depth_sensor(plane, hand, model, 1).texels[1234] == 1010.0f);
    CHECK(run_gpu_depth_sensor(plane, body, model, 1).texels[1234] == 1000.0f);
  }
  SECTION("near cutoff: nearer than range_min is invalid") {
    DepthSensorModel model;
    model.range_min_m = 1.5f;
    CHECK(run_gpu_depth_sensor(plane, body, model, 1).texels[99] == 0.0f);
  }
  SECTION("flying pixels: only at edges, at the configured rate") {
    DepthSensorModel model;
    model.flying_edge_m = 0.05f;
    model.flying_probability = 0.5f;
    HostImage step(w, h, PixelFormat::R32F, 1.0f);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = w / 2; x < w; ++x) step.at(x, y) = 2.0f;  // one vertical edge
    const HostImage gpu = run_gpu_depth_sensor(step, body, model, 9);
    size_t dropped_at_edge = 0, changed_elsewhere = 0;
    for (uint32_t y = 1; y + 1 < h; ++y)
      for (uint32_t x = 1; x + 1 < w; ++x) {
        const bool edge = x == w / 2 - 1 || x == w / 2;
        const float expected = step.at(x, y) * 1000.0f;
        if (edge) dropped_at_edge += gpu.at(x, y) == 0.0f;
        else changed_elsewhere += gpu.at(x, y) != expected;
      }
    CHECK(changed_elsewhere == 0);
    const double edge_pixels = 2.0 * (h - 2);
    CHECK(double(dropped_at_edge) / edge_pixels == Approx(0.25).margin(0.05));  // half of the affected
  }
  SECTION("misregistration shifts depth against color") {
    DepthSensorModel model;
    model.shift_x = 3;
    HostImage ramp(w, h, PixelFormat::R32F);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) ramp.at(x, y) = 0.5f + 0.001f * float(x);
    const HostImage gpu = run_gpu_depth_sensor(ramp, body, model, 1);
    CHECK(gpu.at(100, 10) == std::floor(ramp.at(97, 10) * 1000.0f + 0.5f));
    CHECK(gpu.at(1, 10) == 0.0f);  // shifted in from outside the image
  }
}

TEST_CASE("depth_sensor refuses models it cannot simulate", "[depth_sensor]") {
  DepthSensorModel model;
  model.range_max_m = 0.1f;
  CHECK_THROWS_WITH(passes::check_depth_sensor_model(model), Catch::Contains("range_min_m < range_max_m"));
  model = {};
  model.noise_sigma_at_1m_m = -1.0f;
  CHECK_THROWS_WITH(passes::check_depth_sensor_model(model), Catch::Contains("noise_sigma_at_1m_m"));
  model = {};
  model.flying_probability = 2.0f;
  CHECK_THROWS_WITH(passes::check_depth_sensor_model(model), Catch::Contains("flying_probability"));
  model = {};
  model.skin_bias_m = std::numeric_limits<float>::infinity();
  CHECK_THROWS_WITH(passes::check_depth_sensor_model(model), Catch::Contains("finite"));
}
