#version 460
#extension GL_GOOGLE_include_directive : require
// The receiver's frame in one pass: Eq. 4 (the hand's alpha from its distance), Eq. 5 (the hand
// over the portrait) and the result over the background, per pixel in registers, so that no
// layer is written and read back (common/receiver_layers.glsl). The result equals hand_alpha,
// overlay and composite run one after the other, which stay for inspecting the layers.
#include "shared/config.h"
#include "common/receiver_layers.glsl"

layout(local_size_x = RT_ROW_X, local_size_y = 1) in;
// Set by ReceiverCompositePass from its FusionRamp (passes/hand_alpha.h), where the defaults
// live; the initial values are placeholders that GLSL requires, never used.
layout(constant_id = 0) const float d_min_m = 0.0;
layout(constant_id = 1) const float d_max_m = 0.0;

layout(push_constant) uniform Push { HandAlphaParams params; };

layout(binding = 0, r32f) uniform readonly image2D hand_mask;      // coverage in [0, 1]
layout(binding = 1, rgba32f) uniform readonly image2D hand_color;  // c_g (straight)
layout(binding = 2, rgba32f) uniform readonly image2D portrait;    // c_i, alpha_i (straight)
layout(binding = 3, rgba32f) uniform readonly image2D background;  // rgb, alpha ignored
layout(binding = 4, rgba8) uniform writeonly image2D display;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(display)))) return;
  float alpha_g = fusion_alpha(params.hand_distance_m, d_min_m, d_max_m) * unit_or_zero(imageLoad(hand_mask, pixel).r);
  vec4 fused = overlay_layers(imageLoad(hand_color, pixel).rgb, alpha_g, imageLoad(portrait, pixel));
  imageStore(display, pixel, over_background(fused, imageLoad(background, pixel).rgb));
}
