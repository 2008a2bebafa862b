#version 460
#extension GL_GOOGLE_include_directive : require
// Textured (paper section 3.1.2) and shaded by the light appearance adaption estimated from the
// portrait (shared/hand_shading.h; unlit until it has): the skin texture's albedo times the
// shade, the view's linear depth, the hand mask (full coverage where the mesh is; the fusion
// passes fade it by distance) and the unit normal in the site frame, which the estimate fits to.
#include "shared/config.h"
#include "shared/hand_shading.h"
#include "common/numeric.glsl"
#include "common/shading_basis.glsl"

layout(binding = 2) uniform sampler2D skin_texture;
layout(push_constant) uniform Push { HandRasterParams params; };

layout(location = 0) in vec2 uv;
layout(location = 1) in float camera_z;
layout(location = 2) in vec3 site_normal;

layout(location = 0) out vec4 out_color;    // rgba32f straight alpha, 0 where no hand
layout(location = 1) out float out_depth_m; // r32f, 0 = no hand (the clear value)
layout(location = 2) out float out_mask;    // r32f coverage in [0, 1]
layout(location = 3) out vec4 out_normal;   // rgba32f unit normal, 0 where none

float shade(vec3 n) {
  float b[RT_SHADING_TERMS];
  shading_basis(n, b);
  float s = 0.0;
  for (int k = 0; k < RT_SHADING_TERMS; ++k) s += params.shading[k / 4][k % 4] * b[k];
  return is_finite(s) ? clamp(s, RT_HAND_SHADE_MIN, RT_HAND_SHADE_MAX) : 1.0;
}

void main() {
  float length_sq = dot(site_normal, site_normal);
  // A degenerate normal (collapsed triangles) is drawn unlit rather than guessed.
  bool has_normal = is_finite(length_sq) && length_sq > 1e-12;
  vec3 n = has_normal ? site_normal * inversesqrt(length_sq) : vec3(0.0);
  float s = has_normal ? shade(n) : 1.0;
  out_color = vec4(clamp(texture(skin_texture, uv).rgb * s, 0.0, 1.0), 1.0);
  out_depth_m = camera_z;
  out_mask = 1.0;
  out_normal = vec4(n, has_normal ? 1.0 : 0.0);
}
