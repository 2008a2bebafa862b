#version 460
#extension GL_GOOGLE_include_directive : require
// Resolves a view rendered at `factor` times the resolution (factor odd): color is the mean of
// each pixel's factor x factor samples, as a real sensor integrates light over its pixel (a
// point-sampled ground truth and point-sampled cameras would make every evaluation measure
// aliasing); depth and part take the centre sample, which lies exactly on the pixel's centre.
#include "shared/config.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by SupersampleResolvePass, from the factor it is given
// (passes/supersample_resolve.h), where their defaults live: a kernel refuses to build while one is
// unset, so the initial values below are placeholders that GLSL requires, never used.
layout(constant_id = 0) const int factor = 0;

layout(binding = 0, rgba8) uniform readonly image2D fine_color;
layout(binding = 1, r32f) uniform readonly image2D fine_depth_m;
layout(binding = 2, r32f) uniform readonly image2D fine_part;
layout(binding = 3, rgba8) uniform writeonly image2D color;
layout(binding = 4, r32f) uniform writeonly image2D depth_m;
layout(binding = 5, r32f) uniform writeonly image2D part;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(color)))) return;
  ivec2 first = pixel * factor;
  vec4 sum = vec4(0.0);
  for (int y = 0; y < factor; ++y)
    for (int x = 0; x < factor; ++x) sum += imageLoad(fine_color, first + ivec2(x, y));
  imageStore(color, pixel, sum / float(factor * factor));
  ivec2 centre = first + ivec2(factor / 2);
  imageStore(depth_m, pixel, imageLoad(fine_depth_m, centre));
  imageStore(part, pixel, imageLoad(fine_part, centre));
}
