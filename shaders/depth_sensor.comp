#version 460
#extension GL_GOOGLE_include_directive : require
// A time-of-flight depth camera from the rendered linear depth: millimetres as 16 bits, 0 where
// nothing valid is seen (outside the range, or an effect dropped it). Each effect is a knob
// that defaults to off, and the compiler removes the code of an effect that is off.
#include "shared/config.h"
#include "common/numeric.glsl"
#include "common/random.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

// Knobs, all set by DepthSensorPass, from DepthSensorModel (passes/depth_sensor.h), where their
// defaults live: a kernel refuses to build while one is unset, so the initial values below are
// placeholders that GLSL requires, never used.
layout(constant_id = 0) const float range_min_m = 0.0;
layout(constant_id = 1) const float range_max_m = 0.0;
layout(constant_id = 2) const float noise_sigma_at_1m_m = 0.0;  // depth_noise: sigma grows with z^2
layout(constant_id = 3) const float skin_bias_m = 0.0;          // skin_depth_bias: hand reads farther
layout(constant_id = 4) const float flying_edge_m = 0.0;        // flying_pixels: 0 = off
layout(constant_id = 5) const float flying_probability = 0.0;
layout(constant_id = 6) const int shift_x = 0;                  // misregistration against color
layout(constant_id = 7) const int shift_y = 0;

layout(push_constant) uniform Push { DepthSensorParams params; };

layout(binding = 0, r32f) uniform readonly image2D depth_m;  // 0 = no surface
layout(binding = 1, r32f) uniform readonly image2D part;     // RT_PART_*
layout(binding = 2, r16ui) uniform writeonly uimage2D depth_mm;

float surface_at(ivec2 pixel) {
  ivec2 size = imageSize(depth_m);
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, size))) return 0.0;
  float z = imageLoad(depth_m, pixel).r;
  return is_finite(z) && z > 0.0 ? z : 0.0;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(depth_mm)))) return;
  ivec2 source = pixel - ivec2(shift_x, shift_y);
  float z = surface_at(source);

  if (z > 0.0 && flying_edge_m > 0.0) {
    // At a depth edge the sensor mixes foreground and background returns: some pixels are
    // dropped, some land between the two surfaces.
    float farthest = z;
    bool edge = false;
    for (int i = 0; i < 4; ++i) {
      ivec2 offset = ivec2(i == 0 ? 1 : (i == 1 ? -1 : 0), i == 2 ? 1 : (i == 3 ? -1 : 0));
      float neighbour = surface_at(source + offset);
      if (neighbour == 0.0 || abs(neighbour - z) > flying_edge_m) edge = true;
      if (neighbour > farthest) farthest = neighbour;
    }
    if (edge) {
      float roll = uniform01(pixel_hash(pixel, params.seed, 3u));
      if (roll < 0.5 * flying_probability) z = 0.0;
      else if (roll < flying_probability) z = mix(z, farthest, uniform01(pixel_hash(pixel, params.seed, 4u)));
    }
  }
  if (z > 0.0 && skin_bias_m != 0.0 && imageLoad(part, source).r == RT_PART_HAND) z += skin_bias_m;
  if (z > 0.0 && noise_sigma_at_1m_m > 0.0) z += noise_sigma_at_1m_m * z * z * normal01(pixel, params.seed);

  uint millimetres = 0u;
  // floor(x + 0.5), not round(): GLSL leaves the direction of halves to the driver.
  if (z >= range_min_m && z <= range_max_m) millimetres = uint(clamp(floor(z * 1000.0 + 0.5), 1.0, 65535.0));
  imageStore(depth_mm, pixel, uvec4(millimetres));
}
