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

// One invocation's sums over its pixels, in whole vectors and matrices rather than an array of
// 55 floats: summed term by term through loops, an array stays in indexed memory per lane,
// which cost the pass most of its time. The basis in three blocks b_I = b[3I..3I+2];
// m_IJ[col][row] = sum b_I[row] b_J[col].
struct NormalSums {
  float count;
  mat3 m00, m01, m02, m11, m12, m22;
  vec3 y0, y1, y2;  // sum b_I y
};

void add_pixel(uint i, inout NormalSums s) {
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
  vec3 b0 = vec3(b[0], b[1], b[2]), b1 = vec3(b[3], b[4], b[5]), b2 = vec3(b[6], b[7], b[8]);
  s.count += 1.0;
  s.m00 += outerProduct(b0, b0);
  s.m01 += outerProduct(b0, b1);
  s.m02 += outerProduct(b0, b2);
  s.m11 += outerProduct(b1, b1);
  s.m12 += outerProduct(b1, b2);
  s.m22 += outerProduct(b2, b2);
  s.y0 += b0 * y;
  s.y1 += b1 * y;
  s.y2 += b2 * y;
}

// Term r <= c of the matrix: sum b[r] b[c], from block (r / 3, c / 3).
float matrix_term(NormalSums s, int r, int c) {
  int block = (r / 3) * 3 + c / 3;  // 0 01 02 / - 4 5 / - - 8
  mat3 m = block == 0 ? s.m00 : block == 1 ? s.m01 : block == 2 ? s.m02 : block == 4 ? s.m11 : block == 5 ? s.m12 : s.m22;
  return m[c % 3][r % 3];
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  NormalSums own = NormalSums(0.0, mat3(0.0), mat3(0.0), mat3(0.0), mat3(0.0), mat3(0.0), mat3(0.0), vec3(0.0),
                              vec3(0.0), vec3(0.0));
  // Neighbouring invocations read neighbouring pixels in each step.
  uint base = gl_WorkGroupID.x * RT_SHADING_STATS_GROUP * RT_SHADING_STATS_PIXELS_PER_THREAD + lid;
  for (uint k = 0; k < RT_SHADING_STATS_PIXELS_PER_THREAD; ++k) {
    uint i = base + k * RT_SHADING_STATS_GROUP;
    if (i < params.pixel_count) add_pixel(i, own);
  }
  // The terms in the partials' order: the count, the matrix's upper triangle row by row, sum b y.
  sums[0][lid] = own.count;
  int t = 1;
  for (int r = 0; r < RT_SHADING_TERMS; ++r)
    for (int c = r; c < RT_SHADING_TERMS; ++c) sums[t++][lid] = matrix_term(own, r, c);
  for (int k = 0; k < 3; ++k) {
    sums[1 + RT_SHADING_MATRIX_TERMS + k][lid] = own.y0[k];
    sums[4 + RT_SHADING_MATRIX_TERMS + k][lid] = own.y1[k];
    sums[7 + RT_SHADING_MATRIX_TERMS + k][lid] = own.y2[k];
  }
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
