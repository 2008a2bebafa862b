#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Paper Eq. 3, first half: per workgroup sums of L, alpha, beta and their squares over the hand
// pixels where the image-based portrait (I_i, D_i) and the mesh render (I_g, D_g) both have a
// depth and agree (common/hand_fit_pixel.glsl). Each invocation sums
// RT_COLOR_STATS_PIXELS_PER_THREAD pixels, subgroupAdd sums a subgroup whatever its size (8 on lavapipe, 32 or 64 elsewhere), and one invocation
// adds the subgroups' sums from shared memory after a single barrier.
#include "shared/config.h"
#include "common/lab_alpha_beta.glsl"
#include "common/hand_fit_pixel.glsl"

layout(local_size_x = RT_COLOR_STATS_GROUP) in;

layout(binding = 0, rgba32f) uniform readonly image2D portrait_color;  // straight alpha
layout(binding = 1, r32f) uniform readonly image2D portrait_depth;     // metres, 0 = nothing
layout(binding = 2, rgba32f) uniform readonly image2D mesh_color;
layout(binding = 3, r32f) uniform readonly image2D mesh_depth;
layout(binding = 4, r32f) uniform readonly image2D mesh_mask;
layout(std430, binding = 5) writeonly buffer Partials { ColorStatsPartial partials[]; };
layout(push_constant) uniform Push { ColorStatsParams params; };

shared float sums[13][RT_COLOR_STATS_GROUP];

void add_pixel(uint i, inout float values[13]) {
  ivec2 pixel = ivec2(i % params.width, i / params.width);
  vec4 image = imageLoad(portrait_color, pixel);
  vec4 mesh = imageLoad(mesh_color, pixel);
  float di = imageLoad(portrait_depth, pixel).r, dg = imageLoad(mesh_depth, pixel).r;
  if (!hand_fit_pixel(image, di, mesh, dg, imageLoad(mesh_mask, pixel).r, params)) return;
  vec3 li = rgb_to_lab_alpha_beta(image.rgb), lg = rgb_to_lab_alpha_beta(mesh.rgb);
  values[0] += 1.0;
  for (int c = 0; c < 3; ++c) {
    values[1 + c] += li[c];
    values[4 + c] += li[c] * li[c];
    values[7 + c] += lg[c];
    values[10 + c] += lg[c] * lg[c];
  }
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  float values[13];
  for (int k = 0; k < 13; ++k) values[k] = 0.0;
  // Neighbouring invocations read neighbouring pixels in each step.
  uint base = gl_WorkGroupID.x * RT_COLOR_STATS_GROUP * RT_COLOR_STATS_PIXELS_PER_THREAD + lid;
  for (uint k = 0; k < RT_COLOR_STATS_PIXELS_PER_THREAD; ++k) {
    uint i = base + k * RT_COLOR_STATS_GROUP;
    if (i < params.pixel_count) add_pixel(i, values);
  }
  for (int k = 0; k < 13; ++k) values[k] = subgroupAdd(values[k]);
  if (subgroupElect())
    for (int k = 0; k < 13; ++k) sums[k][gl_SubgroupID] = values[k];
  barrier();
  if (lid != 0) return;
  for (uint s = 1; s < gl_NumSubgroups; ++s)
    for (int k = 0; k < 13; ++k) sums[k][0] += sums[k][s];
  uint g = gl_WorkGroupID.x;
  partials[g].count = vec4(sums[0][0], 0.0, 0.0, 0.0);
  partials[g].image_sum = vec4(sums[1][0], sums[2][0], sums[3][0], 0.0);
  partials[g].image_sum_sq = vec4(sums[4][0], sums[5][0], sums[6][0], 0.0);
  partials[g].mesh_sum = vec4(sums[7][0], sums[8][0], sums[9][0], 0.0);
  partials[g].mesh_sum_sq = vec4(sums[10][0], sums[11][0], sums[12][0], 0.0);
}
