#version 460
#extension GL_GOOGLE_include_directive : require
// Paper Eq. 5: the geometry hand layer over the image-based portrait layer,
//   alpha_f = alpha_g + alpha_i (1 - alpha_g),
//   c_f     = (c_g alpha_g + c_i alpha_i (1 - alpha_g)) / alpha_f.
// The result is stored premultiplied (c_f alpha_f, alpha_f): the division disappears, and
// where alpha_f = 0 the pixel is (0, 0, 0, 0) instead of 0/0.
#include "shared/config.h"
#include "common/receiver_layers.glsl"

layout(local_size_x = RT_ROW_X, local_size_y = 1) in;

layout(binding = 0, rgba32f) uniform readonly image2D hand_color;  // c_g (straight)
layout(binding = 1, r32f) uniform readonly image2D hand_alpha;     // alpha_g
layout(binding = 2, rgba32f) uniform readonly image2D portrait;    // c_i, alpha_i (straight)
layout(binding = 3, rgba32f) uniform writeonly image2D fused;      // premultiplied

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(fused)))) return;
  vec4 fused_layer = overlay_layers(imageLoad(hand_color, pixel).rgb, imageLoad(hand_alpha, pixel).r,
                                    imageLoad(portrait, pixel));
  imageStore(fused, pixel, fused_layer);
}
