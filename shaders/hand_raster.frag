#version 460
#extension GL_GOOGLE_include_directive : require
// Unlit and textured (paper section 3.1.2): the skin texture's albedo, the view's linear depth
// and the hand mask (full coverage where the mesh is; the fusion passes fade it by distance).
#include "shared/config.h"

layout(binding = 2) uniform sampler2D skin_texture;

layout(location = 0) in vec2 uv;
layout(location = 1) in float camera_z;

layout(location = 0) out vec4 out_color;    // rgba32f straight alpha, 0 where no hand
layout(location = 1) out float out_depth_m; // r32f, 0 = no hand (the clear value)
layout(location = 2) out float out_mask;    // r32f coverage in [0, 1]

void main() {
  out_color = vec4(clamp(texture(skin_texture, uv).rgb, 0.0, 1.0), 1.0);
  out_depth_m = camera_z;
  out_mask = 1.0;
}
