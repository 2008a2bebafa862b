#version 460
#extension GL_GOOGLE_include_directive : require
// The fused (premultiplied) layer over an opaque background: c = C_f + c_bg (1 - alpha_f).
// Written as 8-bit RGBA for the display and for PNG output.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(binding = 0, rgba32f) uniform readonly image2D fused;       // premultiplied
layout(binding = 1, rgba32f) uniform readonly image2D background;  // rgb, alpha ignored
layout(binding = 2, rgba8) uniform writeonly image2D display;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(display)))) return;
  vec4 layer = imageLoad(fused, pixel);
  float a_f = unit_or_zero(layer.a);
  // A premultiplied color never exceeds its alpha; clamping to it keeps bad input in range.
  vec3 premultiplied = min(unit_or_zero(layer.rgb), vec3(a_f));
  vec3 c_bg = unit_or_zero(imageLoad(background, pixel).rgb);
  imageStore(display, pixel, vec4(premultiplied + c_bg * (1.0 - a_f), 1.0));
}
