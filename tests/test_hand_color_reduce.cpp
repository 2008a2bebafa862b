// hand_color_reduce (paper Eq. 3, the second half): the GPU's one-workgroup reduction of given
// partial sums against the double-precision reference, on random partials of counts around the
// workgroup size (one, fewer than a workgroup, exactly one, one more, several), with and without
// a previous state to smooth into; and the hard cases: partials past group_count are ignored,
// too few pixels or a non-finite sum leave the state unchanged (the pixel count still recorded),
// no pixel at all; and the weight by frame count (the running mean of the first 1 / smoothing
// frames, then the smoothing), over a chain of frames fed back as the site does. Tolerance: means and sigmas 1e-4 absolute (float sums over thousands of
// pixels); the header's counts exactly.
#include <cmath>
#include <limits>
#include <random>

#include "hand/appearance_adaption.h"
#include "passes/hand_color_reduce.h"
#include "passes/hand_color_transfer.h"
#include "support/appearance_states.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::AppearanceState;
using shader_abi::ColorStatsPartial;

namespace {

// Partials as the statistics pass writes them: each the sums over a few pixels whose L, alpha,
// beta lie in [-1, 0.5].
std::vector<ColorStatsPartial> random_partials(std::mt19937& rng, size_t groups) {
  std::uniform_real_distribution<float> value(-1.0f, 0.5f);
  std::uniform_int_distribution<int> pixels(0, 8);
  std::vector<ColorStatsPartial> partials(groups);
  for (ColorStatsPartial& p : partials) {
    const int n = pixels(rng);
    p.count[0] = float(n);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const float image = value(rng), mesh = value(rng);
        p.image_sum[c] += image;
        p.image_sum_sq[c] += image * image;
        p.mesh_sum[c] += mesh;
        p.mesh_sum_sq[c] += mesh * mesh;
      }
  }
  return partials;
}

AppearanceState run_gpu_hand_color_reduce(const std::vector<ColorStatsPartial>& partials, const AppearanceState& state,
                        const shader_abi::ColorStatsReduceParams& params) {
  const passes::HandColorReducePass pass(test::gpu());
  test::PassHarness gpu("hand_color_reduce");
  pass.add_to(gpu.graph(), gpu.input_buffer("partials", partials),
              gpu.input_buffer("appearance state", std::span(&state, 1), true), [params] { return params; });
  return gpu.run().value<AppearanceState>("appearance state");
}

void require_state_matches(const AppearanceState& gpu, const AppearanceState& reference) {
  CHECK(gpu.header == reference.header);
  for (std::array<float, 4> AppearanceState::*field : {&AppearanceState::image_mean, &AppearanceState::image_sigma,
                                                        &AppearanceState::mesh_mean, &AppearanceState::mesh_sigma})
    for (int c = 0; c < 4; ++c) {
      INFO("channel " << c << ": gpu " << (gpu.*field)[c] << ", reference " << (reference.*field)[c]);
      REQUIRE(std::isfinite((gpu.*field)[c]));
      REQUIRE(std::abs((gpu.*field)[c] - (reference.*field)[c]) <= 1e-4);
    }
}

shader_abi::ColorStatsReduceParams params_for(size_t groups) {
  return {uint32_t(groups), 10.0f, 0.25f, passes::kSigmaFloor};
}

}  // namespace

TEST_CASE("hand_color_reduce matches the reference on random partials", "[hand_color_reduce][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(23);
  for (size_t groups : {size_t(1), size_t(37), size_t(RT_COLOR_STATS_GROUP), size_t(RT_COLOR_STATS_GROUP + 1), size_t(1000)}) {
    for (const AppearanceState& previous : {AppearanceState{}, test::previous_appearance_state()}) {
      INFO(groups << " partials, " << (previous.header[0] > 0.5f ? "smoothed into a previous state" : "no previous state"));
      const std::vector<ColorStatsPartial> partials = random_partials(rng, groups);
      auto params = params_for(groups);
      params.min_pixels = 1.0f;  // a single partial of a few pixels is still used
      const AppearanceState gpu = run_gpu_hand_color_reduce(partials, previous, params);
      const AppearanceState reference = passes::color_reduce_reference(partials, previous, params);
      require_state_matches(gpu, reference);
      if (reference.header[2] >= 1.0f) {
        CHECK(gpu.header[0] == 1.0f);
        CHECK(gpu.header[1] == previous.header[1] + 1.0f);
      }
    }
  }
}

TEST_CASE("hand_color_reduce hard cases", "[hand_color_reduce][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(24);
  const AppearanceState previous = test::previous_appearance_state();
  const std::vector<ColorStatsPartial> partials = random_partials(rng, 300);
  double pixels = 0;
  for (const auto& p : partials) pixels += p.count[0];

  SECTION("smoothing: the new statistics weigh `smoothing`, the update is counted") {
    const AppearanceState gpu = run_gpu_hand_color_reduce(partials, previous, params_for(partials.size()));
    require_state_matches(gpu, passes::color_reduce_reference(partials, previous, params_for(partials.size())));
    CHECK(gpu.header[1] == 5.0f);
    CHECK(gpu.header[2] == float(pixels));
  }
  SECTION("partials past group_count are not read") {
    std::vector<ColorStatsPartial> with_garbage = partials;
    ColorStatsPartial garbage{};
    garbage.count = {1e6f, 0.0f, 0.0f, 0.0f};
    garbage.image_sum = {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, 0.0f};
    with_garbage.insert(with_garbage.end(), 50, garbage);
    const auto params = params_for(partials.size());
    require_state_matches(run_gpu_hand_color_reduce(with_garbage, previous, params), run_gpu_hand_color_reduce(partials, previous, params));
  }
  SECTION("too few pixels leave the statistics unchanged") {
    auto strict = params_for(partials.size());
    strict.min_pixels = float(pixels + 1);
    const AppearanceState unchanged = run_gpu_hand_color_reduce(partials, previous, strict);
    CHECK(unchanged.header[1] == 4.0f);
    CHECK(unchanged.image_mean == previous.image_mean);
    CHECK(unchanged.mesh_sigma == previous.mesh_sigma);
    CHECK(unchanged.header[2] == float(pixels));
    require_state_matches(unchanged, passes::color_reduce_reference(partials, previous, strict));
  }
  SECTION("a non-finite sum leaves the statistics unchanged") {
    std::vector<ColorStatsPartial> infinite = partials;
    infinite[7].mesh_sum_sq[1] = std::numeric_limits<float>::infinity();
    const AppearanceState unchanged = run_gpu_hand_color_reduce(infinite, previous, params_for(infinite.size()));
    CHECK(unchanged.header[1] == 4.0f);
    CHECK(unchanged.mesh_sigma == previous.mesh_sigma);
    CHECK(unchanged.header[2] == float(pixels));
  }
  SECTION("no valid pixel at all") {
    const std::vector<ColorStatsPartial> empty(40);
    const AppearanceState result = run_gpu_hand_color_reduce(empty, AppearanceState{}, params_for(empty.size()));
    CHECK(result.header[0] == 0.0f);
    CHECK(result.header[2] == 0.0f);
    CHECK(result.image_mean == AppearanceState{}.image_mean);
  }
}

TEST_CASE("hand_color_reduce weighs a frame by the frames fitted before it, as the reference", "[hand_color_reduce][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(25);
  const auto params = params_for(200);
  // A chain of frames, each folded into the state the one before left: GPU against GPU's own
  // previous state, the reference against its own; both against the weights written out.
  AppearanceState gpu{}, reference{};
  for (int frame = 0; frame < 7; ++frame) {
    INFO("frame " << frame);
    const std::vector<ColorStatsPartial> partials = random_partials(rng, 200);
    const AppearanceState before = reference;
    gpu = run_gpu_hand_color_reduce(partials, gpu, params);
    reference = passes::color_reduce_reference(partials, reference, params);
    require_state_matches(gpu, reference);
    CHECK(gpu.header[1] == float(frame + 1));
    // The frame's own statistics (weight 1 into an empty state) against the weight of its count.
    const AppearanceState alone = passes::color_reduce_reference(partials, AppearanceState{}, params);
    const double w = hand::appearance_weight(frame, params.smoothing);
    CHECK(w == (frame < 4 ? 1.0 / (frame + 1) : 0.25));
    for (int c = 0; c < 3; ++c) {
      CHECK(reference.image_mean[c] == Approx(before.image_mean[c] + w * (alone.image_mean[c] - before.image_mean[c])).margin(1e-6));
      CHECK(reference.mesh_sigma[c] == Approx(before.mesh_sigma[c] + w * (alone.mesh_sigma[c] - before.mesh_sigma[c])).margin(1e-6));
    }
  }
}
