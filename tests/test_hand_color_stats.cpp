// hand_color_stats + hand_color_reduce (paper Eq. 3 statistics): the GPU's parallel reductions
// against the double-precision reference on random images of odd sizes (the pixels split over
// workgroups unevenly, the last one partly empty), and the hard cases: no valid pixel, black
// and saturated pixels, NaN input, depths that disagree, too few pixels, temporal smoothing.
// Tolerances: sums 1e-3 relative + 1e-3 absolute (float accumulation over thousands of pixels);
// means and sigmas 1e-4 absolute.
#include <cmath>
#include <limits>
#include <random>

#include "hand/color_space.h"
#include "passes/hand_color_reduce.h"
#include "passes/hand_color_stats.h"
#include "passes/hand_color_transfer.h"
#include "support/appearance_states.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::AppearanceState;
using passes::ColorStatsPartial;

namespace {

struct Inputs {
  HostImage portrait_color, portrait_depth, mesh_color, mesh_depth, mesh_mask;
};

Inputs random_inputs(std::mt19937& rng, uint32_t w, uint32_t h) {
  Inputs in{test::random_image(rng, w, h, PixelFormat::RGBA32F, 0.0f, 1.0f), test::random_image(rng, w, h, PixelFormat::R32F, 0.5f, 0.6f),
            test::random_image(rng, w, h, PixelFormat::RGBA32F, 0.0f, 1.0f), test::random_image(rng, w, h, PixelFormat::R32F, 0.5f, 0.6f),
            test::random_image(rng, w, h, PixelFormat::R32F, 0.0f, 1.0f)};
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      in.mesh_mask.at(x, y) = in.mesh_mask.at(x, y) > 0.3f ? 1.0f : 0.0f;
      in.portrait_color.at(x, y, 3) = unit(rng) > 0.1f ? 1.0f : 0.0f;
      if (unit(rng) < 0.1f) in.portrait_depth.at(x, y) = 0.0f;
    }
  return in;
}

struct GpuResult {
  std::vector<ColorStatsPartial> partials;
  AppearanceState state;
};

GpuResult run_gpu_hand_color_stats(const Inputs& in, const AppearanceState& state, const shader_abi::ColorStatsReduceParams& reduce) {
  const passes::HandColorStatsPass stats(test::gpu());
  const passes::HandColorReducePass reducer(test::gpu());
  test::PassHarness gpu("hand_color_stats");
  const uint32_t groups = passes::color_stats_group_count(in.mesh_color.width, in.mesh_color.height);
  vk::Buffer& partials = gpu.output_buffer<ColorStatsPartial>("partials", groups);
  stats.add_to(gpu.graph(), gpu.input("portrait color", in.portrait_color), gpu.input("portrait depth", in.portrait_depth),
               gpu.input("mesh color", in.mesh_color), gpu.input("mesh depth", in.mesh_depth),
               gpu.input("mesh mask", in.mesh_mask), partials);
  auto params = reduce;
  params.group_count = groups;
  reducer.add_to(gpu.graph(), partials, gpu.input_buffer("appearance state", std::span(&state, 1), true),
                 [params] { return params; });
  const test::PassOutputs out = gpu.run();
  return {out.values<ColorStatsPartial>("partials"), out.value<AppearanceState>("appearance state")};
}

void require_sums_match(const std::vector<ColorStatsPartial>& partials, const passes::ColorSums& reference) {
  double count = 0;
  Eigen::Vector3d sums[4] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (const auto& p : partials) {
    count += p.count[0];
    for (int c = 0; c < 3; ++c) {
      sums[0][c] += p.image_sum[c];
      sums[1][c] += p.image_sum_sq[c];
      sums[2][c] += p.mesh_sum[c];
      sums[3][c] += p.mesh_sum_sq[c];
      REQUIRE(std::isfinite(p.image_sum[c]));
      REQUIRE(std::isfinite(p.mesh_sum_sq[c]));
    }
  }
  REQUIRE(count == reference.count);
  const Eigen::Vector3d expected[4] = {reference.image_sum, reference.image_sum_sq, reference.mesh_sum, reference.mesh_sum_sq};
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) REQUIRE(std::abs(sums[k][c] - expected[k][c]) <= 1e-3 + 1e-3 * std::abs(expected[k][c]));
}

void require_state_matches_hand_color_stats(const AppearanceState& gpu, const AppearanceState& reference) {
  for (int c = 0; c < 4; ++c) {
    REQUIRE(gpu.header[c] == Approx(reference.header[c]).margin(1e-3));
    for (std::array<float, 4> AppearanceState::*field : {&AppearanceState::image_mean, &AppearanceState::image_sigma, &AppearanceState::mesh_mean,
                              &AppearanceState::mesh_sigma}) {
      REQUIRE(std::isfinite((gpu.*field)[c]));
      REQUIRE(std::abs((gpu.*field)[c] - (reference.*field)[c]) <= 1e-4);
    }
  }
}

const shader_abi::ColorStatsReduceParams kReduce{0, 10.0f, 0.25f, passes::kSigmaFloor};

}  // namespace

TEST_CASE("hand_color_stats and hand_color_reduce match the reference on random images of odd sizes") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(21);
  for (auto [w, h] : std::vector<std::pair<uint32_t, uint32_t>>{{1, 1}, {17, 1}, {1, 33}, {37, 29}, {160, 77}}) {
    INFO(w << "x" << h);
    const Inputs in = random_inputs(rng, w, h);
    const AppearanceState empty{};
    const GpuResult gpu = run_gpu_hand_color_stats(in, empty, kReduce);
    const auto sums = passes::color_stats_reference(in.portrait_color, in.portrait_depth, in.mesh_color, in.mesh_depth,
                                                    in.mesh_mask, passes::color_stats_params(w, h));
    require_sums_match(gpu.partials, sums);
    auto params = kReduce;
    params.group_count = uint32_t(gpu.partials.size());
    require_state_matches_hand_color_stats(gpu.state, passes::color_reduce_reference(gpu.partials, empty, params));
    if (sums.count >= 10) CHECK(gpu.state.header[0] == 1.0f);
  }
}

TEST_CASE("Color statistics hard cases: black, saturated, NaN, depth disagreement, too few pixels, smoothing") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(8);
  const uint32_t w = 41, h = 23;
  Inputs in = random_inputs(rng, w, h);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (uint32_t x = 0; x < w; ++x) {
    for (uint32_t c = 0; c < 3; ++c) {
      in.portrait_color.at(x, 0, c) = 0.0f;  // black: log of zero
      in.mesh_color.at(x, 1, c) = 1.0f;      // saturated
    }
    in.portrait_color.at(x, 2, 1) = nan;
    in.mesh_depth.at(x, 3) = nan;
    in.portrait_depth.at(x, 4) = in.mesh_depth.at(x, 4) + 0.06f;  // more than 5 cm apart
    in.mesh_mask.at(x, 0) = in.mesh_mask.at(x, 1) = in.mesh_mask.at(x, 2) = in.mesh_mask.at(x, 3) = in.mesh_mask.at(x, 4) = 1.0f;
    in.portrait_color.at(x, 0, 3) = in.portrait_color.at(x, 1, 3) = in.portrait_color.at(x, 2, 3) = 1.0f;
  }
  const auto params = passes::color_stats_params(w, h);
  const auto sums = passes::color_stats_reference(in.portrait_color, in.portrait_depth, in.mesh_color, in.mesh_depth, in.mesh_mask, params);
  // A previous state, to see the smoothing.
  const AppearanceState previous = test::previous_appearance_state();
  const GpuResult gpu = run_gpu_hand_color_stats(in, previous, kReduce);
  require_sums_match(gpu.partials, sums);
  auto reduce = kReduce;
  reduce.group_count = uint32_t(gpu.partials.size());
  require_state_matches_hand_color_stats(gpu.state, passes::color_reduce_reference(gpu.partials, previous, reduce));
  CHECK(gpu.state.header[1] == 5.0f);

  SECTION("too few pixels leave the statistics unchanged") {
    auto strict = kReduce;
    strict.min_pixels = float(w * h + 1);
    const GpuResult unchanged = run_gpu_hand_color_stats(in, previous, strict);
    CHECK(unchanged.state.header[1] == 4.0f);
    CHECK(unchanged.state.image_mean == previous.image_mean);
    CHECK(unchanged.state.header[2] == Approx(sums.count));
  }
  SECTION("no valid pixel at all") {
    Inputs none = in;
    for (float& m : none.mesh_mask.texels) m = 0.0f;
    const GpuResult result = run_gpu_hand_color_stats(none, AppearanceState{}, kReduce);
    CHECK(result.state.header[0] == 0.0f);
    CHECK(result.state.header[2] == 0.0f);
  }
}

TEST_CASE("L-alpha-beta round trip and CIEDE2000 against Sharma's published pairs") {
  for (const Eigen::Vector3d& rgb : {Eigen::Vector3d(0.8, 0.6, 0.5), Eigen::Vector3d(0.05, 0.5, 0.95), Eigen::Vector3d(0.3, 0.19, 0.13)})
    CHECK((hand::lab_alpha_beta_to_rgb(hand::rgb_to_lab_alpha_beta(rgb)) - rgb).norm() < 2e-3);
  CHECK(hand::rgb_to_lab_alpha_beta(Eigen::Vector3d::Zero()).allFinite());
  // Sharma, Wu, Dalal (2005), test pairs 1, 7, 17, 18, 19, 20.
  CHECK(hand::delta_e_2000({50, 2.6772, -79.7751}, {50, 0, -82.7485}) == Approx(2.0425).margin(1e-4));
  CHECK(hand::delta_e_2000({50, 0, 0}, {50, -1, 2}) == Approx(2.3669).margin(1e-4));
  CHECK(hand::delta_e_2000({50, 2.5, 0}, {73, 25, -18}) == Approx(27.1492).margin(1e-4));
  CHECK(hand::delta_e_2000({50, 2.5, 0}, {56, -27, -3}) == Approx(31.9030).margin(1e-4));
  CHECK(hand::delta_e_2000({50, 2.5, 0}, {58, 24, 15}) == Approx(19.4535).margin(1e-4));
  CHECK(hand::delta_e_2000({50, 2.5, 0}, {50, 3.1736, 0.5854}) == Approx(1.0).margin(1e-4));
  CHECK(hand::rgb_to_cielab(Eigen::Vector3d(1, 1, 1)).x() == Approx(100.0).margin(1e-3));
}
