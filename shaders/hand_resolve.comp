#version 460
#extension GL_GOOGLE_include_directive : require
// The geometry hand rasterized at `factor` times the target's resolution, resolved to it: the
// mask is the fraction of a pixel's samples the hand covers, so the mesh's silhouette blends
// into the portrait across its edge pixels instead of stepping; the color is the mean over the
// covered samples alone (straight, so that the fusion's alpha carries the coverage once); the
// depth is the nearest covered sample's.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_ROW_X, local_size_y = 1) in;
// Set by HandResolvePass from the factor it is given (passes/hand_resolve.h); the placeholder
// below is never used (a kernel refuses to build while one is unset).
layout(constant_id = 0) const int factor = 0;

layout(binding = 0, rgba32f) uniform readonly image2D fine_color;  // straight, 1 on the hand
layout(binding = 1, r32f) uniform readonly image2D fine_mask;      // coverage in [0, 1]
layout(binding = 2, r32f) uniform readonly image2D fine_depth_m;   // camera z, 0 = no hand
layout(binding = 3, rgba32f) uniform writeonly image2D color;
layout(binding = 4, r32f) uniform writeonly image2D mask;
layout(binding = 5, r32f) uniform writeonly image2D depth_m;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(color)))) return;
  ivec2 first = pixel * factor;
  vec3 color_sum = vec3(0.0);
  float coverage = 0.0;
  float nearest = 0.0;
  for (int y = 0; y < factor; ++y)
    for (int x = 0; x < factor; ++x) {
      ivec2 sample_at = first + ivec2(x, y);
      float covered = unit_or_zero(imageLoad(fine_mask, sample_at).r);
      vec4 c = imageLoad(fine_color, sample_at);
      // A non-finite sample adds no color; its coverage still counts, as black.
      color_sum += covered * vec3(is_finite(c.r) ? c.r : 0.0, is_finite(c.g) ? c.g : 0.0, is_finite(c.b) ? c.b : 0.0);
      coverage += covered;
      float z = imageLoad(fine_depth_m, sample_at).r;
      if (covered > 0.0 && is_finite(z) && z > 0.0 && (nearest == 0.0 || z < nearest)) nearest = z;
    }
  bool any_covered = coverage > 0.0;
  imageStore(color, pixel, any_covered ? vec4(color_sum / coverage, 1.0) : vec4(0.0));
  imageStore(mask, pixel, vec4(coverage / float(factor * factor)));
  imageStore(depth_m, pixel, vec4(nearest));
}
