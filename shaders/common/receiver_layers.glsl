// The receiver's three equations per pixel, shared by the passes that run them one by one
// (hand_alpha, overlay, composite: each layer kept in an image for inspection) and the one
// that runs them in registers (receiver_composite), so the two cannot drift apart. Mirrored by
// passes::hand_alpha_reference, overlay_reference and composite_reference.
#ifndef REMOTETOUCH_RECEIVER_LAYERS_GLSL
#define REMOTETOUCH_RECEIVER_LAYERS_GLSL
#include "common/numeric.glsl"

// Eq. 4's ramp: 1 at d_min and nearer, 0 at d_max and farther. A NaN or infinite distance
// means "no geometry hand", never a NaN pixel.
float fusion_alpha(float d, float d_min, float d_max) {
  if (!is_finite(d)) return 0.0;
  return (d_max - clamp(d, d_min, d_max)) / (d_max - d_min);
}

// Eq. 5, premultiplied (c_f alpha_f, alpha_f): the division disappears, and where alpha_f = 0
// the pixel is (0, 0, 0, 0) instead of 0/0. Straight inputs; non-finite ones count as 0.
vec4 overlay_layers(vec3 hand_color, float hand_alpha, vec4 portrait) {
  vec3 c_g = unit_or_zero(hand_color);
  float a_g = unit_or_zero(hand_alpha);
  vec3 c_i = unit_or_zero(portrait.rgb);
  float a_i = unit_or_zero(portrait.a);
  float portrait_weight = a_i * (1.0 - a_g);
  return vec4(c_g * a_g + c_i * portrait_weight, a_g + portrait_weight);
}

// The fused (premultiplied) layer over an opaque background. A premultiplied color never
// exceeds its alpha; clamping to it keeps bad input in range.
vec4 over_background(vec4 fused, vec3 background) {
  float a_f = unit_or_zero(fused.a);
  vec3 premultiplied = min(unit_or_zero(fused.rgb), vec3(a_f));
  return vec4(premultiplied + unit_or_zero(background) * (1.0 - a_f), 1.0);
}

#endif
