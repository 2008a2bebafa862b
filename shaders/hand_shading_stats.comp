#version 460
#extension GL_GOOGLE_include_directive : require
// Appearance adaption's light estimate, first half: per workgroup the normal equations of the
// least-squares fit y ~ sum_k c_k b_k(n) over Eq. 3's pixels (common/hand_fit_pixel.glsl), where
// y is the portrait's brightness over the untouched template's at the pixel (so the texture's
// own detail, nails and creases, is not read as light) and n the mesh's unit normal there
// (shared/hand_shading.h). Pixels whose normal is not a unit vector are skipped. Plain shared
// memory tree reduction: 55 terms do not fit one value per invocation of a larger group.
#include "shared/config.h"
#include "shared/hand_shading.h"
#include "common/hand_fit_pixel.glsl"
#include "common/shading_basis.glsl"

layout(local_size_x = RT_SHADING_STATS_GROUP) in;

layout(binding = 0, rgba32f) uniform readonly image2D portrait_color;  // straight alpha
layout(binding = 1, r32f) uniform readonly image2D portrait_depth;     // metres, 0 = nothing
layout(binding = 2, rgba32f) uniform readonly image2D mesh_color;      // the untouched template
layout(binding = 3, r32f) uniform readonly image2D mesh_depth;
layout(binding = 4, r32f) uniform readonly image2D mesh_mask;
layout(binding = 5, rgba32f) uniform readonly image2D mesh_normal;     // xyz unit normal, 0 = none
layout(std430, binding = 6) writeonly buffer Partials { ShadingPartial partials[]; };
layout(push_constant) uniform Push { ColorStatsParams params; };

shared float sums[RT_SHADING_SUM_TERMS][RT_SHADING_STATS_GROUP];

void add_pixel(uint i, inout float values[RT_SHADING_SUM_TERMS]) {
  ivec2 pixel = ivec2(i % params.width, i / params.width);
  vec4 image = imageLoad(portrait_color, pixel);
  vec4 mesh = imageLoad(mesh_color, pixel);
  float di = imageLoad(portrait_depth, pixel).r, dg = imageLoad(mesh_depth, pixel).r;
  if (!hand_fit_pixel(image, di, mesh, dg, imageLoad(mesh_mask, pixel).r, params)) return;
  vec3 n = imageLoad(mesh_normal, pixel).xyz;
  float length_sq = dot(n, n);
  if (!(is_finite(length_sq) && abs(length_sq - 1.0) < 1e-3)) return;
  // hand_fit_usable keeps every channel above the black level: no division by zero.
  float y = (image.r + image.g + image.b) / (mesh.r + mesh.g + mesh.b);
  float b[RT_SHADING_TERMS];
  shading_basis(n, b);
  values[0] += 1.0;
  int t = 1;
  for (int r = 0; r < RT_SHADING_TERMS; ++r)
    for (int c = r; c < RT_SHADING_TERMS; ++c) values[t++] += b[r] * b[c];
  for (int k = 0; k < RT_SHADING_TERMS; ++k) values[1 + RT_SHADING_MATRIX_TERMS + k] += b[k] * y;
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  float values[RT_SHADING_SUM_TERMS];
  for (int k = 0; k < RT_SHADING_SUM_TERMS; ++k) values[k] = 0.0;
  // Neighbouring invocations read neighbouring pixels in each step.
  uint base = gl_WorkGroupID.x * RT_SHADING_STATS_GROUP * RT_SHADING_STATS_PIXELS_PER_THREAD + lid;
  for (uint k = 0; k < RT_SHADING_STATS_PIXELS_PER_THREAD; ++k) {
    uint i = base + k * RT_SHADING_STATS_GROUP;
    if (i < params.pixel_count) add_pixel(i, values);
  }
  for (int k = 0; k < RT_SHADING_SUM_TERMS; ++k) sums[k][lid] = values[k];
  for (uint stride = RT_SHADING_STATS_GROUP / 2; stride > 0; stride >>= 1) {
    barrier();
    if (lid < stride)
      for (int k = 0; k < RT_SHADING_SUM_TERMS; ++k) sums[k][lid] += sums[k][lid + stride];
  }
  if (lid != 0) return;
  uint g = gl_WorkGroupID.x;
  for (int v = 0; v < RT_SHADING_PARTIAL_VEC4S; ++v)
    for (int c = 0; c < 4; ++c) {
      int k = v * 4 + c;
      partials[g].sums[v][c] = k < RT_SHADING_SUM_TERMS ? sums[k][0] : 0.0;
    }
}
