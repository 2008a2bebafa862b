// depth_outliers pass: GPU against the C++ reference on random depth images of odd sizes (surfaces
// with noise, holes, flying pixels, lone outliers, NaN, negative and out-of-range texels), and the
// hard cases with the answer known. Tolerance: none. Both decide each pixel from whole
// millimetres and one float product, so every pixel must be equal; and no NaN or Inf.
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "camera/k4a_recording_reader.h"
#include "passes/depth_outliers.h"
#include "support/output_dir.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::DepthOutliersSettings;

namespace {

HostImage run_gpu_depth_outliers(const HostImage& depth_mm, const DepthOutliersSettings& settings = {}) {
  const passes::DepthOutliersPass pass(test::gpu(), settings);
  test::PassHarness gpu("depth_outliers");
  pass.add_to(gpu.graph(), gpu.input("depth mm", depth_mm),
              gpu.output("filtered", depth_mm.width, depth_mm.height, PixelFormat::R16U));
  return gpu.run().image("filtered");
}

// GPU and reference equal; returns the result.
HostImage outliers_both(const HostImage& depth_mm, const DepthOutliersSettings& settings = {}) {
  const HostImage gpu = run_gpu_depth_outliers(depth_mm, settings);
  const HostImage ref = passes::depth_outliers_reference(depth_mm, settings);
  RT_REQUIRE_MATCHES(gpu, ref, 0.0, 0.0);
  return gpu;
}

// A person at 0.8-1.0 m before a wall at 2 m, noisy, with holes, flying pixels along the person's
// outline and lone outliers; some texels not even millimetres.
HostImage outliers_random_scene(std::mt19937& rng, uint32_t w, uint32_t h) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 8.0f);
  HostImage depth(w, h, PixelFormat::R16U, 0.0f);
  const float cx = unit(rng) * float(w), cy = unit(rng) * float(h), r = (0.2f + 0.4f * unit(rng)) * float(std::max(w, h));
  const float slope = 20.0f * (unit(rng) - 0.5f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const float d = std::hypot(float(x) - cx, float(y) - cy);
      float z = d < r ? 850.0f + slope * float(x) * 0.1f + noise(rng) : 2000.0f + noise(rng);
      if (std::abs(d - r) < 1.0f) z = 850.0f + (2000.0f - 850.0f) * unit(rng);  // mixed returns at the edge
      const float p = unit(rng);
      if (p < 0.08f) z = 0.0f;                                   // no measurement
      else if (p < 0.10f) z = 300.0f + 5000.0f * unit(rng);      // multipath
      else if (p < 0.11f) z = std::numeric_limits<float>::quiet_NaN();
      else if (p < 0.115f) z = -40.0f;
      else if (p < 0.12f) z = 70000.0f;
      else if (p < 0.14f) z += 0.4f;                             // not a whole millimetre
      depth.at(x, y, 0) = z;
    }
  return depth;
}

}  // namespace

TEST_CASE("depth_outliers: GPU matches the reference on random scenes of odd sizes", "[gpu][depth_outliers]") {
  std::mt19937 rng(47);
  const uint32_t sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 2}, {13, 9}, {33, 17}, {101, 57}, {320, 288}};
  for (const auto& size : sizes) {
    INFO(size[0] << "x" << size[1]);
    const HostImage depth = outliers_random_scene(rng, size[0], size[1]);
    outliers_both(depth);
    outliers_both(depth, {.max_step_mm = 5.0f, .max_step_relative = 0.0f, .min_support = 5});
    outliers_both(depth, {.max_step_mm = 0.0f, .max_step_relative = 0.1f, .min_support = 1});
  }
}

TEST_CASE("depth_outliers: the hard cases", "[gpu][depth_outliers]") {
  SECTION("nothing measured stays so") {
    const HostImage out = outliers_both(HostImage(17, 11, PixelFormat::R16U, 0.0f));
    for (const float v : out.texels) REQUIRE(v == 0.0f);
  }
  SECTION("a plane, corners and borders included, is kept whole") {
    HostImage plane(15, 7, PixelFormat::R16U);
    for (uint32_t y = 0; y < 7; ++y)
      for (uint32_t x = 0; x < 15; ++x) plane.at(x, y, 0) = float(1000 + 7 * x + 3 * y);  // tilted, 7 mm a pixel
    const HostImage out = outliers_both(plane);
    for (size_t i = 0; i < out.texels.size(); ++i) REQUIRE(out.texels[i] == plane.texels[i]);
  }
  SECTION("a step edge: the flying pixels between the surfaces go, both surfaces stay") {
    // Columns 0-5 a person at 800 mm, 6 a line of mixed returns, 7-12 the wall at 2000 mm.
    HostImage edge(13, 9, PixelFormat::R16U);
    for (uint32_t y = 0; y < 9; ++y)
      for (uint32_t x = 0; x < 13; ++x) edge.at(x, y, 0) = x < 6 ? 800.0f : x == 6 ? float(1100 + 90 * y) : 2000.0f;
    const HostImage out = outliers_both(edge);
    for (uint32_t y = 0; y < 9; ++y)
      for (uint32_t x = 0; x < 13; ++x) {
        INFO(x << ", " << y);
        REQUIRE(out.at(x, y, 0) == (x == 6 ? 0.0f : edge.at(x, y, 0)));
      }
  }
  SECTION("a lone outlier in a surface goes, its neighbours stay; a lone measurement goes") {
    HostImage plane(9, 9, PixelFormat::R16U, 1200.0f);
    plane.at(4, 4, 0) = 3100.0f;
    HostImage out = outliers_both(plane);
    REQUIRE(out.at(4, 4, 0) == 0.0f);
    REQUIRE(out.at(3, 4, 0) == 1200.0f);
    REQUIRE(out.at(0, 0, 0) == 1200.0f);
    HostImage lone(9, 9, PixelFormat::R16U, 0.0f);
    lone.at(4, 4, 0) = 1500.0f;
    out = outliers_both(lone);
    REQUIRE(out.at(4, 4, 0) == 0.0f);
    // Nearer than the step: the holes around it are still no support.
    lone.at(4, 4, 0) = 20.0f;
    REQUIRE(outliers_both(lone).at(4, 4, 0) == 0.0f);
  }
  SECTION("NaN, negative and too large texels: NaN and negative are no measurement, the rest clamps") {
    HostImage odd(3, 3, PixelFormat::R16U, 65535.0f);
    odd.at(0, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    odd.at(2, 2, 0) = -5.0f;
    odd.at(1, 1, 0) = 1e9f;
    const HostImage out = outliers_both(odd);
    REQUIRE(out.at(0, 0, 0) == 0.0f);
    REQUIRE(out.at(2, 2, 0) == 0.0f);
    REQUIRE(out.at(1, 1, 0) == 65535.0f);
  }
  SECTION("degenerate: one pixel has no neighbour; min_support 0 keeps every measurement") {
    HostImage one(1, 1, PixelFormat::R16U, 900.0f);
    REQUIRE(outliers_both(one).at(0, 0, 0) == 0.0f);
    REQUIRE(outliers_both(one, {.min_support = 0}).at(0, 0, 0) == 900.0f);
  }
  SECTION("bad settings are refused") {
    REQUIRE_THROWS_AS(passes::DepthOutliersPass(test::gpu(), {.max_step_mm = -1.0f}), std::invalid_argument);
    REQUIRE_THROWS_AS(passes::DepthOutliersPass(test::gpu(), {.max_step_relative = std::nanf("")}), std::invalid_argument);
    REQUIRE_THROWS_AS(passes::depth_outliers_reference(HostImage(2, 2, PixelFormat::R16U), {.min_support = 9}),
                      std::invalid_argument);
  }
}

namespace {

// Whether `z` lies on a true surface: within 3 cm + 3 % of the true depth of the pixel or of one
// of its eight neighbours (a pixel on an outline may take either side's depth).
bool outliers_on_true_surface(const HostImage& truth, uint32_t x, uint32_t y, float z) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = int(x) + dx, qy = int(y) + dy;
      if (qx < 0 || qy < 0 || qx >= int(truth.width) || qy >= int(truth.height)) continue;
      const float t = truth.at(uint32_t(qx), uint32_t(qy), 0);
      if (t > 0.0f && std::abs(z - t) <= 30.0f + 0.03f * t) return true;
    }
  return false;
}

}  // namespace

// The measurement in docs/real-cameras.md: a recording written by `simulate --format k4a` (the
// cli_simulate_k4a fixture: clap, site A, six cameras, WFOV 2x2 binned depth) given what a
// time-of-flight camera adds to its exact depth: noise (8 mm), flying pixels (each pixel on the
// far side of a depth step over 10 cm becomes, with probability one half, a mix of the two
// surfaces' returns) and multipath (0.2 % of the pixels 10-50 % too far). Counted: the points off
// every true surface before and after the pass, and the true-surface points it removed.
TEST_CASE("depth_outliers: flying pixels on a recording, counted", "[gpu][depth_outliers]") {
  const std::filesystem::path dir = test::output_dir("simulate-k4a");
  const char* names[] = {"top-left", "top-centre", "top-right", "bottom-left", "bottom-centre", "bottom-right"};
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 8.0f);
  size_t measured = 0, flying = 0, multipath = 0, off_before = 0, off_after = 0, surface = 0, surface_lost = 0;
  for (const char* name : names) {
    camera::k4a::RecordingReader reader(dir / (std::string(name) + ".mkv"));
    const std::optional<camera::k4a::Capture> capture = reader.next_capture();
    REQUIRE(capture);
    const HostImage& truth = capture->depth_mm;
    REQUIRE(truth.width > 0);
    HostImage sensed = truth;
    for (uint32_t y = 0; y < truth.height; ++y)
      for (uint32_t x = 0; x < truth.width; ++x) {
        const float z = truth.at(x, y, 0);
        if (z <= 0.0f) continue;
        float out = z + noise(rng);
        float nearer = z;
        for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int qx = int(x) + dx, qy = int(y) + dy;
          if (qx < 0 || qy < 0 || qx >= int(truth.width) || qy >= int(truth.height)) continue;
          const float t = truth.at(uint32_t(qx), uint32_t(qy), 0);
          if (t > 0.0f && t < nearer - 100.0f) nearer = t;
        }
        if (nearer < z && unit(rng) < 0.5f) {
          const float a = 0.1f + 0.8f * unit(rng);
          out = a * nearer + (1.0f - a) * z;
          ++flying;
        } else if (unit(rng) < 0.002f) {
          out = z * (1.1f + 0.4f * unit(rng));
          ++multipath;
        }
        sensed.at(x, y, 0) = std::round(out);
      }
    const HostImage filtered = run_gpu_depth_outliers(sensed);
    RT_REQUIRE_MATCHES(filtered, passes::depth_outliers_reference(sensed), 0.0, 0.0);
    for (uint32_t y = 0; y < truth.height; ++y)
      for (uint32_t x = 0; x < truth.width; ++x) {
        const float before = sensed.at(x, y, 0), after = filtered.at(x, y, 0);
        if (before <= 0.0f) continue;
        ++measured;
        const bool on_surface = outliers_on_true_surface(truth, x, y, before);
        off_before += !on_surface;
        off_after += !on_surface && after > 0.0f;
        surface += on_surface;
        surface_lost += on_surface && after == 0.0f;
      }
  }
  std::printf("depth_outliers on %s (6 cameras, one capture each): %zu points measured, %zu made flying, %zu "
              "multipath\n  off every true surface: %zu before, %zu after (%.1f %% removed)\n  on a true surface: "
              "%zu, of which removed %zu (%.2f %%)\n",
              dir.string().c_str(), measured, flying, multipath, off_before, off_after,
              100.0 * double(off_before - off_after) / double(std::max<size_t>(off_before, 1)), surface, surface_lost,
              100.0 * double(surface_lost) / double(std::max<size_t>(surface, 1)));
  REQUIRE(off_before > 100);
  CHECK(double(off_after) < 0.1 * double(off_before));
  CHECK(double(surface_lost) < 0.02 * double(surface));
}
