#version 460
#extension GL_GOOGLE_include_directive : require
// Resolves the fusion buffer into the target view's depth (metres of camera z, 0 = nothing) and
// fills the cracks between splats. An empty pixel is filled with the mean of its neighbours only
// when most of them are set (a crack, not the outside of a silhouette) and they agree in depth
// (one surface, not a depth edge), so filling never bleeds across edges.
#include "shared/config.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrFusePass, from FuseSettings (passes/ibr_fuse.h), where their defaults live:
// a kernel refuses to build while one is unset, so the initial values below are placeholders that
// GLSL requires, never used.
layout(constant_id = 0) const bool average_fusion = false;
layout(constant_id = 1) const int fill_min_neighbours = 0;  // of 8
layout(constant_id = 2) const float fill_tolerance_m = 0.0;

layout(std430, binding = 0) readonly buffer Fusion { uint fusion[]; };
layout(binding = 1, r32f) uniform writeonly image2D fused_depth;

float resolved(ivec2 pixel, ivec2 size) {
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, size))) return 0.0;
  uint index = uint(pixel.y * size.x + pixel.x);
  uint n = uint(size.x * size.y);
  uint bits = fusion[index];
  if (bits == RT_IBR_EMPTY_DEPTH_BITS) return 0.0;
  if (average_fusion) {
    uint count = fusion[2u * n + index];
    if (count > 0u) return float(fusion[n + index]) * 1e-5 / float(count);
  }
  return uintBitsToFloat(bits);
}

void main() {
  ivec2 size = imageSize(fused_depth);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  float z = resolved(pixel, size);
  if (z == 0.0) {
    int count = 0;
    float sum = 0.0, nearest = 1e30, farthest = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        float neighbour = resolved(pixel + ivec2(dx, dy), size);
        if (neighbour <= 0.0) continue;
        ++count;
        sum += neighbour;
        nearest = min(nearest, neighbour);
        farthest = max(farthest, neighbour);
      }
    if (count >= fill_min_neighbours && farthest - nearest <= fill_tolerance_m) z = sum / float(count);
  }
  imageStore(fused_depth, pixel, vec4(z));
}
