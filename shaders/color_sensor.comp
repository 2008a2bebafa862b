#version 460
#extension GL_GOOGLE_include_directive : require
// A color camera's response: a gain and a white balance per channel, clipped like a sensor.
// Off (gain 1, balance 1) unless the scene sets the color_gain effect.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

// Knobs, all set by ColorSensorPass, from ColorSensorModel (passes/color_sensor.h), where their
// defaults live: a kernel refuses to build while one is unset, so the initial values below are
// placeholders that GLSL requires, never used.
layout(constant_id = 0) const float gain = 0.0;
layout(constant_id = 1) const float balance_r = 0.0;
layout(constant_id = 2) const float balance_g = 0.0;
layout(constant_id = 3) const float balance_b = 0.0;

layout(binding = 0, rgba8) uniform readonly image2D rendered;
layout(binding = 1, rgba8) uniform writeonly image2D sensed;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(sensed)))) return;
  vec4 color = imageLoad(rendered, pixel);
  vec3 response = color.rgb * gain * vec3(balance_r, balance_g, balance_b);
  imageStore(sensed, pixel, vec4(unit_or_zero(response), color.a));
}
