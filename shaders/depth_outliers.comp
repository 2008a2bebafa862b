#version 460
#extension GL_GOOGLE_include_directive : require
// A time-of-flight depth image without its flying pixels and lone outliers, before fusion.
//
// Where a depth pixel straddles an edge, the sensor mixes the returns of the near and the far
// surface and reports a depth between them: a "flying pixel", floating in the air between a
// person and the wall behind. Multipath and low signal leave single pixels far off any surface.
// Both have few neighbours at their own depth; a pixel on a surface has several, even on an
// outline (a convex corner of a surface still has three of its eight) or on a thin part. So a
// pixel is kept when at least `min_support` of its eight neighbours were measured within the
// step a surface may make between neighbours, and set to 0 (no measurement) otherwise. A line
// of flying pixels along an edge supports itself with at most two neighbours, hence three.
// The comparison is on whole millimetres and one float product: the C++ reference
// (passes/depth_outliers.cpp) decides every pixel the same way.
#include "shared/config.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, set by DepthOutliersPass from DepthOutliersSettings (passes/depth_outliers.h), where
// their defaults live: the initial values are placeholders that GLSL requires, never used.
layout(constant_id = 0) const float max_step_mm = 0.0;        // neighbours within this
layout(constant_id = 1) const float max_step_relative = 0.0;  // or this times the depth agree
layout(constant_id = 2) const int min_support = 0;            // agreeing neighbours to be kept

layout(binding = 0, r16ui) uniform readonly uimage2D depth_mm;  // 0 = no measurement
layout(binding = 1, r16ui) uniform writeonly uimage2D filtered_mm;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(depth_mm);
  if (any(greaterThanEqual(pixel, size))) return;
  uint z = imageLoad(depth_mm, pixel).r;
  uint kept = 0u;
  if (z != 0u) {
    float step = max(max_step_mm, max_step_relative * float(z));
    int support = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 q = pixel + ivec2(dx, dy);
        if ((dx == 0 && dy == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
        uint n = imageLoad(depth_mm, q).r;
        if (n != 0u && abs(float(n) - float(z)) <= step) ++support;
      }
    }
    if (support >= min_support) kept = z;
  }
  imageStore(filtered_mm, pixel, uvec4(kept, 0u, 0u, 0u));
}
