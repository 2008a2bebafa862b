#version 460
#extension GL_GOOGLE_include_directive : require
// Paper Eq. 3, second half: one workgroup adds the partial sums, turns them into means and
// standard deviations, and folds them into the running (temporally smoothed) statistics. Too
// few pixels, or anything non-finite, leaves the statistics - and so the texture - unchanged.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_COLOR_STATS_GROUP) in;

layout(std430, binding = 0) readonly buffer Partials { ColorStatsPartial partials[]; };
layout(std430, binding = 1) buffer State { AppearanceState state; };
layout(push_constant) uniform Push { ColorStatsReduceParams params; };

shared float sums[13][RT_COLOR_STATS_GROUP];

void main() {
  uint lid = gl_LocalInvocationID.x;
  float values[13];
  for (int k = 0; k < 13; ++k) values[k] = 0.0;
  for (uint g = lid; g < params.group_count; g += RT_COLOR_STATS_GROUP) {
    values[0] += partials[g].count.x;
    for (int c = 0; c < 3; ++c) {
      values[1 + c] += partials[g].image_sum[c];
      values[4 + c] += partials[g].image_sum_sq[c];
      values[7 + c] += partials[g].mesh_sum[c];
      values[10 + c] += partials[g].mesh_sum_sq[c];
    }
  }
  for (int k = 0; k < 13; ++k) sums[k][lid] = values[k];
  for (uint stride = RT_COLOR_STATS_GROUP / 2; stride > 0; stride >>= 1) {
    barrier();
    if (lid < stride)
      for (int k = 0; k < 13; ++k) sums[k][lid] += sums[k][lid + stride];
  }
  if (lid != 0) return;
  float n = sums[0][0];
  state.header.z = n;
  if (!(n >= max(params.min_pixels, 1.0))) return;
  vec3 mean_i, mean_g, sigma_i, sigma_g;
  for (int c = 0; c < 3; ++c) {
    mean_i[c] = sums[1 + c][0] / n;
    mean_g[c] = sums[7 + c][0] / n;
    // E[x^2] - E[x]^2 may round below zero for a flat region.
    sigma_i[c] = sqrt(max(sums[4 + c][0] / n - mean_i[c] * mean_i[c], 0.0));
    sigma_g[c] = sqrt(max(sums[10 + c][0] / n - mean_g[c] * mean_g[c], 0.0));
  }
  bool finite = true;
  for (int c = 0; c < 3; ++c)
    finite = finite && is_finite(mean_i[c]) && is_finite(mean_g[c]) && is_finite(sigma_i[c]) && is_finite(sigma_g[c]);
  if (!finite) return;
  // Counted in frames, never seconds (hand/appearance_adaption.h): the running mean of the frames so
  // far while 1 / (n + 1) exceeds `smoothing`, then the exponential average; the first frame weighs 1.
  float fitted_before = state.header.x > 0.5 ? max(state.header.y, 0.0) : 0.0;
  float w = max(1.0 / (fitted_before + 1.0), clamp(params.smoothing, 0.0, 1.0));
  state.image_mean.xyz = mix(state.image_mean.xyz, mean_i, w);
  state.image_sigma.xyz = mix(state.image_sigma.xyz, sigma_i, w);
  state.mesh_mean.xyz = mix(state.mesh_mean.xyz, mean_g, w);
  state.mesh_sigma.xyz = mix(state.mesh_sigma.xyz, sigma_g, w);
  state.header.x = 1.0;
  state.header.y += 1.0;
}
