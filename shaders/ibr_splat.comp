#version 460
#extension GL_GOOGLE_include_directive : require
// Depth reprojection (paper 3.1.1): every foreground point of every view is projected into the
// target view and splatted over the pixels its depth pixel covers there. The fused depth keeps
// the nearest surface, the paper's min-filter: positive floats order as their bit patterns, so a
// 32-bit atomicMin on the bits is a depth test with no race. With `accumulate_average` the pass
// instead sums the depths that agree with that minimum, for the averaging baseline (run after
// the min pass).
#include "shared/config.h"
#include "common/ibr_camera.glsl"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
layout(constant_id = 0) const bool accumulate_average = false;
layout(constant_id = 1) const float footprint_scale = 1.0;   // splat side over the projected pixel size
layout(constant_id = 2) const float max_footprint_px = 6.0;
layout(constant_id = 3) const float average_tolerance_m = 0.1;  // depths this far behind the nearest join its average

layout(binding = 0, rgba32f) uniform readonly image2D points;  // site xyz, camera z; 0 = none
// [0, n): nearest depth bits; [n, 2n): sum of agreeing depths (10 micrometre units); [2n, 3n): their count.
layout(std430, binding = 1) buffer Fusion { uint fusion[]; };

void main() {
  int view = int(gl_GlobalInvocationID.z);
  ivec2 size = ivec2(lens_size(cameras[view].depth));
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec4 point = imageLoad(points, ivec2(pixel.x, pixel.y + view * size.y));
  if (point.w <= 0.0) return;
  vec3 p = transform_point(target.camera_from_site, point.xyz);
  if (p.z <= 1e-4) return;  // behind the eye: not in the target view
  vec2 centre = target.pinhole.xy * (p.xy / p.z) + target.pinhole.zw;
  // Far outside the image (grazing the eye plane): skip before converting to integers.
  if (!is_finite(centre.x) || !is_finite(centre.y)) return;
  if (any(lessThan(centre, vec2(-max_footprint_px))) || any(greaterThan(centre, target.size.xy + max_footprint_px))) return;
  // A depth pixel is point.w / fx_depth metres wide at its surface; seen from the eye that is
  // this many target pixels (up to the surface's tilt, which the hole filling absorbs).
  float footprint = footprint_scale * (point.w / cameras[view].depth.pinhole.x) * target.pinhole.x / p.z;
  float half_side = 0.5 * clamp(footprint, 1.0, max_footprint_px);
  ivec2 target_size = ivec2(target.size.xy);
  ivec2 first = max(ivec2(ceil(centre - half_side)), ivec2(0));
  ivec2 last = min(ivec2(floor(centre + half_side)), target_size - 1);
  uint bits = floatBitsToUint(p.z);
  uint n = uint(target_size.x * target_size.y);
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      uint index = uint(y * target_size.x + x);
      if (!accumulate_average) {
        atomicMin(fusion[index], bits);
      } else if (p.z <= uintBitsToFloat(fusion[index]) + average_tolerance_m) {
        atomicAdd(fusion[n + index], uint(floor(p.z * 1e5 + 0.5)));
        atomicAdd(fusion[2u * n + index], 1u);
      }
    }
}
