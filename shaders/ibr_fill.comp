#version 460
#extension GL_GOOGLE_include_directive : require
// Fills the portrait's small enclosed holes: pixels that no view saw colour for (alpha under one
// half) but that have a covered pixel within `radius_px` in each of the four directions along the
// rows and columns. Such a pixel lies inside the person, in a crack between splats or a spot that
// every camera's view of was blocked; left empty, the receiver shows the background through the
// user. It takes the mean of the four nearest covered pixels' colours, each weighed by the
// inverse of its distance, and full alpha. A pixel open to one side within the radius (outside the
// silhouette, or in a concave bay of it, such as the gap between fingers) stays as it is.
// It runs over the listed tiles alone (the portrait's surface tiles; the reset before the
// listing zeroed the rest of `filled`), so the background far from the user costs nothing.
// Depth is not filled: the colour of a filled pixel is a guess no camera measured, and a pixel no
// view saw has no depth, so appearance adaption, which needs one, never fits to that guess.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrFillPass (passes/ibr_fill.h): a kernel refuses to build while one is unset,
// so the initial value below is a placeholder that GLSL requires, never used.
layout(constant_id = 0) const int radius_px = 0;

layout(binding = 0, rgba32f) uniform readonly image2D portrait;  // straight color, alpha
layout(binding = 1, rgba32f) uniform writeonly image2D filled;   // the same, holes filled
layout(std430, binding = 2) readonly buffer Tiles { uvec4 tiles[]; };  // column, row, 0, 0: one workgroup each

// Written so that a NaN alpha counts as uncovered.
bool covered(vec4 color) { return color.a >= 0.5; }

vec4 finite_portrait_value(vec4 color) { return vec4(unit_or_zero(color.rgb), color.a > 0.0 ? min(color.a, 1.0) : 0.0); }

void main() {
  const ivec2 pixel = ivec2(tiles[gl_WorkGroupID.x].xy * uvec2(RT_TILE_X, RT_TILE_Y) + gl_LocalInvocationID.xy);
  const ivec2 size = imageSize(portrait);
  if (any(greaterThanEqual(pixel, size))) return;
  const vec4 own = imageLoad(portrait, pixel);
  if (covered(own)) {
    imageStore(filled, pixel, finite_portrait_value(own));
    return;
  }
  const ivec2 directions[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
  vec3 weighted = vec3(0.0);
  float weight_sum = 0.0;
  int enclosed_sides = 0;
  for (int d = 0; d < 4; ++d) {
    int distance = 1;
    vec4 nearest = vec4(0.0);
    for (; distance <= radius_px; ++distance) {
      const ivec2 p = pixel + directions[d] * distance;
      if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) {
        distance = radius_px + 1;
        break;
      }
      nearest = imageLoad(portrait, p);
      if (covered(nearest)) break;
    }
    if (distance > radius_px) break;  // open on this side: the remaining sides need no search
    const float weight = 1.0 / float(distance);
    weighted += unit_or_zero(nearest.rgb) * weight;
    weight_sum += weight;
    ++enclosed_sides;
  }
  imageStore(filled, pixel, enclosed_sides == 4 ? vec4(weighted / weight_sum, 1.0) : finite_portrait_value(own));
}
