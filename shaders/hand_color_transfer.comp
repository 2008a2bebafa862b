#version 460
#extension GL_GOOGLE_include_directive : require
// Paper Eq. 3 applied to the texture: T -> T', per L-alpha-beta channel
// c' = min(sigma_i / max(sigma_g, floor), max_contrast) (c - m_g) + m_i. Until statistics exist
// T' = T; a texel that would come out non-finite keeps its template color.
#include "shared/config.h"
#include "common/lab_alpha_beta.glsl"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Set by HandColorTransferPass (passes/hand_color_transfer.h), where its default lives: a kernel
// refuses to build while it is unset, so the value below is a placeholder GLSL requires.
layout(constant_id = 0) const float max_contrast = 0.0;

layout(binding = 0, rgba32f) uniform readonly image2D template_texture;
layout(binding = 1, rgba32f) uniform writeonly image2D adapted_texture;
layout(std430, binding = 2) readonly buffer State { AppearanceState state; };
layout(push_constant) uniform Push { ColorTransferParams params; };

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, imageSize(adapted_texture)))) return;
  vec4 t = imageLoad(template_texture, texel);
  vec4 result = t;
  bool state_finite = true;
  for (int c = 0; c < 3; ++c)
    state_finite = state_finite && is_finite(state.image_mean[c]) && is_finite(state.image_sigma[c]) &&
                   is_finite(state.mesh_mean[c]) && is_finite(state.mesh_sigma[c]);
  if (state.header.x > 0.5 && state_finite) {
    vec3 lab = rgb_to_lab_alpha_beta(clamp(t.rgb, 0.0, 1.0));
    vec3 scale = min(state.image_sigma.xyz / max(state.mesh_sigma.xyz, vec3(max(params.sigma_floor, 1e-6))), vec3(max_contrast));
    vec3 rgb = lab_alpha_beta_to_rgb(scale * (lab - state.mesh_mean.xyz) + state.image_mean.xyz);
    bool finite = is_finite(rgb.r) && is_finite(rgb.g) && is_finite(rgb.b);
    if (finite) result.rgb = clamp(rgb, 0.0, 1.0);
  }
  imageStore(adapted_texture, texel, result);
}
