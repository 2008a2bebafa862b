// hand_shading_stats (appearance adaption's light estimate, its normal equations) against the
// double-precision reference on random images of odd sizes (the pixels split over workgroups
// unevenly, the last one partly empty), and the hard cases: no valid pixel, zero alpha, NaN
// depth and color, normals that are zero, NaN or not of unit length, black template pixels.
// Then the fit (hand/shading_fit.h) from the GPU's sums recovers a known light.
// Tolerances: sums 1e-3 relative + 1e-3 absolute (float accumulation over 4096 pixels a group);
// the recovered shade, relative to its value at one normal, within 0.08 rms and 0.25 at worst of
// the true one (nine terms cannot follow the two-sided light's kink where n is normal to the
// light: 0.065 rms is the least-squares optimum there), and under a third of the unlit error.
#include <cmath>
#include <limits>
#include <random>

#include "hand/shading_fit.h"
#include "passes/hand_shading_stats.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::ShadingPartial;

namespace {

struct InputsHandShadingStats {
  HostImage portrait_color, portrait_depth, mesh_color, mesh_depth, mesh_mask, mesh_normal;
};

Eigen::Vector3d random_unit(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  Eigen::Vector3d n(gauss(rng), gauss(rng), gauss(rng));
  return n.norm() > 1e-6 ? n.normalized() : Eigen::Vector3d::UnitZ();
}

InputsHandShadingStats random_inputs_hand_shading_stats(std::mt19937& rng, uint32_t w, uint32_t h) {
  InputsHandShadingStats in{test::random_image(rng, w, h, PixelFormat::RGBA32F, 0.05f, 0.95f), test::random_image(rng, w, h, PixelFormat::R32F, 0.5f, 0.6f),
            test::random_image(rng, w, h, PixelFormat::RGBA32F, 0.05f, 0.95f), test::random_image(rng, w, h, PixelFormat::R32F, 0.5f, 0.6f),
            test::random_image(rng, w, h, PixelFormat::R32F, 0.0f, 1.0f), HostImage(w, h, PixelFormat::RGBA32F)};
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      in.mesh_mask.at(x, y) = in.mesh_mask.at(x, y) > 0.2f ? 1.0f : 0.0f;
      in.portrait_color.at(x, y, 3) = unit(rng) > 0.1f ? 1.0f : 0.0f;
      const Eigen::Vector3d n = random_unit(rng);
      for (uint32_t c = 0; c < 3; ++c) in.mesh_normal.at(x, y, c) = float(n[c]);
      in.mesh_normal.at(x, y, 3) = 1.0f;
    }
  return in;
}

std::vector<ShadingPartial> run_gpu_hand_shading_stats(const InputsHandShadingStats& in) {
  const passes::HandShadingStatsPass pass(test::gpu());
  test::PassHarness gpu("hand_shading_stats");
  const uint32_t groups = passes::shading_stats_group_count(in.mesh_color.width, in.mesh_color.height);
  vk::Buffer& partials = gpu.output_buffer<ShadingPartial>("partials", groups);
  pass.add_to(gpu.graph(), gpu.input("portrait color", in.portrait_color), gpu.input("portrait depth", in.portrait_depth),
              gpu.input("mesh color", in.mesh_color), gpu.input("mesh depth", in.mesh_depth), gpu.input("mesh mask", in.mesh_mask),
              gpu.input("mesh normal", in.mesh_normal), partials);
  return gpu.run().values<ShadingPartial>("partials");
}

hand::ShadingSums reference_of(const InputsHandShadingStats& in) {
  return passes::shading_stats_reference(in.portrait_color, in.portrait_depth, in.mesh_color, in.mesh_depth, in.mesh_mask,
                                         in.mesh_normal);
}

void require_sums_match_hand_shading_stats(const std::vector<ShadingPartial>& partials, const hand::ShadingSums& reference) {
  for (const auto& p : partials)
    for (const auto& v : p.sums)
      for (float value : v) REQUIRE(std::isfinite(value));
  const hand::ShadingSums gpu = hand::add_shading_partials(partials);
  REQUIRE(gpu.count == reference.count);
  auto close = [](double a, double b) { return std::abs(a - b) <= 1e-3 + 1e-3 * std::abs(b); };
  for (int r = 0; r < hand::kShadingTerms; ++r) {
    INFO("term " << r);
    REQUIRE(close(gpu.rhs[r], reference.rhs[r]));
    for (int c = 0; c < hand::kShadingTerms; ++c) REQUIRE(close(gpu.normal(r, c), reference.normal(r, c)));
  }
}

}  // namespace

TEST_CASE("hand_shading_stats matches the reference on random images of odd sizes") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(31);
  for (auto [w, h] : std::vector<std::pair<uint32_t, uint32_t>>{{1, 1}, {19, 1}, {1, 37}, {67, 61}, {131, 71}}) {
    INFO(w << "x" << h);
    const InputsHandShadingStats in = random_inputs_hand_shading_stats(rng, w, h);
    const hand::ShadingSums reference = reference_of(in);
    require_sums_match_hand_shading_stats(run_gpu_hand_shading_stats(in), reference);
    if (w * h > 100) CHECK(reference.count > w * h / 2);
  }
}

TEST_CASE("hand_shading_stats hard cases: zero alpha, NaN, normals that are not unit vectors, nothing valid") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(5);
  const uint32_t w = 43, h = 29;
  InputsHandShadingStats in = random_inputs_hand_shading_stats(rng, w, h);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (uint32_t x = 0; x < w; ++x) {
    for (uint32_t y = 0; y < 9; ++y) in.mesh_mask.at(x, y) = in.portrait_color.at(x, y, 3) = 1.0f;
    in.portrait_color.at(x, 0, 3) = 0.0f;                               // zero alpha
    in.portrait_depth.at(x, 1) = nan;                                   // NaN distance
    for (uint32_t c = 0; c < 3; ++c) in.mesh_normal.at(x, 2, c) = 0.0f;  // no normal
    in.mesh_normal.at(x, 3, 1) = nan;
    for (uint32_t c = 0; c < 3; ++c) in.mesh_normal.at(x, 4, c) *= 0.5f;  // not of unit length
    in.mesh_normal.at(x, 5, 0) = inf;
    for (uint32_t c = 0; c < 3; ++c) in.mesh_color.at(x, 6, c) = 0.0f;  // black template: no ratio
    in.portrait_color.at(x, 7, 2) = nan;
    in.mesh_depth.at(x, 8) = -1.0f;                                     // behind the camera
  }
  const hand::ShadingSums reference = reference_of(in);
  require_sums_match_hand_shading_stats(run_gpu_hand_shading_stats(in), reference);
  // None of the spoiled rows counted.
  InputsHandShadingStats spoiled_only = in;
  for (uint32_t y = 9; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) spoiled_only.mesh_mask.at(x, y) = 0.0f;
  CHECK(reference_of(spoiled_only).count == 0);
  const hand::ShadingSums none = hand::add_shading_partials(run_gpu_hand_shading_stats(spoiled_only));
  CHECK(none.count == 0);
  CHECK(none.normal.isZero());
  CHECK(none.rhs.isZero());
  hand::ShadingFit fit(0.25, 16);
  CHECK_FALSE(fit.add_frame(none));
  CHECK(fit.coefficients() == hand::unlit_shading());
}

TEST_CASE("The light estimate from the GPU's sums recovers a known light") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(77);
  const uint32_t w = 97, h = 53;
  InputsHandShadingStats in = random_inputs_hand_shading_stats(rng, w, h);
  // The simulator's two-sided light (shaders/person_raster.frag), on normals facing the camera.
  const Eigen::Vector3d light = Eigen::Vector3d(1, 2, 3).normalized();
  auto true_shade = [&](const Eigen::Vector3d& n) { return 0.35 + 0.65 * std::abs(n.dot(light)); };
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      Eigen::Vector3d n = random_unit(rng);
      if (n.z() > 0) n.z() = -n.z();
      for (uint32_t c = 0; c < 3; ++c) {
        in.mesh_normal.at(x, y, c) = float(n[c]);
        in.mesh_color.at(x, y, c) = 0.6f;
        in.portrait_color.at(x, y, c) = float(0.5 * true_shade(n));
      }
      in.mesh_depth.at(x, y) = in.portrait_depth.at(x, y);
    }
  hand::ShadingFit fit(0.25, 16);
  REQUIRE(fit.add_frame(hand::add_shading_partials(run_gpu_hand_shading_stats(in))));
  const hand::ShadingVector c = fit.coefficients();
  REQUIRE(c.allFinite());
  // The fitted shade, up to its normalisation, follows the true one: compare the two normalised
  // by their values at two normals.
  double worst = 0, squares = 0, unlit_squares = 0;
  const Eigen::Vector3d reference_normal = -light.cwiseAbs().normalized();
  for (int i = 0; i < 200; ++i) {
    Eigen::Vector3d n = random_unit(rng);
    if (n.z() > 0) n.z() = -n.z();
    const double fitted = hand::shade(c, n) / hand::shade(c, reference_normal);
    const double truth = true_shade(n) / true_shade(reference_normal);
    worst = std::max(worst, std::abs(fitted - truth));
    squares += (fitted - truth) * (fitted - truth);
    unlit_squares += (1.0 - truth) * (1.0 - truth);
  }
  const double rms = std::sqrt(squares / 200), unlit_rms = std::sqrt(unlit_squares / 200);
  INFO("relative shade error: rms " << rms << ", worst " << worst << "; unlit rms " << unlit_rms);
  CHECK(rms < 0.08);
  CHECK(worst < 0.25);
  CHECK(rms < 0.3 * unlit_rms);
}
