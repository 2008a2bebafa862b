#version 460
#extension GL_GOOGLE_include_directive : require
// Paper Eq. 4: alpha of the geometry hand layer from the hand's distance to the screen,
// alpha_g = (d_max - clip(d, d_min, d_max)) / (d_max - d_min) on hand pixels, 0 elsewhere.
// The mask is read as coverage in [0, 1] so an anti-aliased mask edge fades too.
#include "shared/config.h"
#include "common/receiver_layers.glsl"

layout(local_size_x = RT_ROW_X, local_size_y = 1) in;

// Knobs, all set by HandAlphaPass, from FusionRamp (passes/hand_alpha.h), where their defaults
// live: a kernel refuses to build while one is unset, so the initial values below are placeholders
// that GLSL requires, never used.
layout(constant_id = 0) const float d_min_m = 0.0;
layout(constant_id = 1) const float d_max_m = 0.0;

layout(push_constant) uniform Push { HandAlphaParams params; };

layout(binding = 0, r32f) uniform readonly image2D hand_mask;
layout(binding = 1, r32f) uniform writeonly image2D hand_alpha;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(hand_alpha)))) return;
  float coverage = unit_or_zero(imageLoad(hand_mask, pixel).r);
  imageStore(hand_alpha, pixel, vec4(fusion_alpha(params.hand_distance_m, d_min_m, d_max_m) * coverage));
}
