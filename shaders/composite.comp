#version 460
#extension GL_GOOGLE_include_directive : require
// The fused (premultiplied) layer over an opaque background: c = C_f + c_bg (1 - alpha_f).
// Written as 8-bit RGBA for the display and for PNG output.
#include "shared/config.h"
#include "common/receiver_layers.glsl"

layout(local_size_x = RT_ROW_X, local_size_y = 1) in;

layout(binding = 0, rgba32f) uniform readonly image2D fused;       // premultiplied
layout(binding = 1, rgba32f) uniform readonly image2D background;  // rgb, alpha ignored
layout(binding = 2, rgba8) uniform writeonly image2D display;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(display)))) return;
  imageStore(display, pixel, over_background(imageLoad(fused, pixel), imageLoad(background, pixel).rgb));
}
