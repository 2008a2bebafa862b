#include "passes/hand_color_reduce.h"

#include <algorithm>
#include <cmath>

#include "hand/appearance_adaption.h"
#include "hand_color_reduce.comp.h"

namespace rt::passes {

HandColorReducePass::HandColorReducePass(vk::Context& context) : kernel_(context, "hand_color_reduce", hand_color_reduce_comp_spirv) {}

void HandColorReducePass::add_to(vk::FrameGraph& graph, vk::Buffer& partials, vk::Buffer& state,
                                 std::function<ColorStatsReduceParams()> params, const std::string& pass_name) const {
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"Partials", &partials}, {"State", &state}},
      .threads = {RT_COLOR_STATS_GROUP, 1, 1},
      .push_constants = vk::push_constants_from<ColorStatsReduceParams>(std::move(params)),
  });
}

AppearanceState color_reduce_reference(std::span<const shader_abi::ColorStatsPartial> partials, const AppearanceState& state,
                                       const ColorStatsReduceParams& params) {
  double sums[13] = {};
  for (uint32_t g = 0; g < params.group_count && g < partials.size(); ++g) {
    sums[0] += partials[g].count[0];
    for (int c = 0; c < 3; ++c) {
      sums[1 + c] += partials[g].image_sum[c];
      sums[4 + c] += partials[g].image_sum_sq[c];
      sums[7 + c] += partials[g].mesh_sum[c];
      sums[10 + c] += partials[g].mesh_sum_sq[c];
    }
  }
  AppearanceState out = state;
  const double n = sums[0];
  out.header[2] = float(n);
  if (!(n >= std::max(double(params.min_pixels), 1.0))) return out;
  double mean_i[3], mean_g[3], sigma_i[3], sigma_g[3];
  bool finite = true;
  for (int c = 0; c < 3; ++c) {
    mean_i[c] = sums[1 + c] / n;
    mean_g[c] = sums[7 + c] / n;
    sigma_i[c] = std::sqrt(std::max(sums[4 + c] / n - mean_i[c] * mean_i[c], 0.0));
    sigma_g[c] = std::sqrt(std::max(sums[10 + c] / n - mean_g[c] * mean_g[c], 0.0));
    finite &= std::isfinite(mean_i[c]) && std::isfinite(mean_g[c]) && std::isfinite(sigma_i[c]) && std::isfinite(sigma_g[c]);
  }
  if (!finite) return out;
  const double w = hand::appearance_weight(state.header[0] > 0.5f ? double(state.header[1]) : 0.0, params.smoothing);
  for (int c = 0; c < 3; ++c) {
    out.image_mean[c] = float(state.image_mean[c] + w * (mean_i[c] - state.image_mean[c]));
    out.image_sigma[c] = float(state.image_sigma[c] + w * (sigma_i[c] - state.image_sigma[c]));
    out.mesh_mean[c] = float(state.mesh_mean[c] + w * (mean_g[c] - state.mesh_mean[c]));
    out.mesh_sigma[c] = float(state.mesh_sigma[c] + w * (sigma_g[c] - state.mesh_sigma[c]));
  }
  out.header[0] = 1.0f;
  out.header[1] += 1.0f;
  return out;
}

}  // namespace rt::passes
