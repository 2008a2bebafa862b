#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// Unstructured lumigraph blending (Buehler et al. 2001, common/ulr_blend.glsl) of the warp's
// atlases into the portrait. Alpha is the coverage: 0 where no view sees the surface point
// (never a NaN), 1 where one does; the feather only shapes weights.
#include "shared/config.h"
#include "common/numeric.glsl"
#include "common/ulr_blend.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrBlendPass, from BlendSettings (passes/ibr_blend.h), where their defaults
// live: a kernel refuses to build while one is unset, so the initial values below are placeholders
// that GLSL requires, never used.
layout(constant_id = 0) const int best_views = 0;  // k
layout(constant_id = 1) const float resolution_weight = 0.0;  // radians of penalty per metre

layout(binding = 0, r32f) uniform readonly image2D fused_depth;
layout(binding = 1, rgba32f) uniform readonly image2D warped;
layout(binding = 2, rgba32f) uniform readonly image2D features;
layout(binding = 3, rgba32f) uniform writeonly image2D portrait;        // straight color, alpha
layout(binding = 4, r32f) uniform writeonly image2D portrait_depth;     // metres, 0 = nothing
layout(push_constant) uniform Push { IbrBlendParams params; };

void main() {
  ivec2 size = imageSize(portrait);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  float penalty[RT_IBR_MAX_VIEWS];  // -1: not a candidate
  float feather[RT_IBR_MAX_VIEWS];
  vec3 color[RT_IBR_MAX_VIEWS];
  bool seen = false;
  for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    penalty[v] = -1.0;
    feather[v] = 0.0;
    color[v] = vec3(0.0);
    if (v >= int(params.view_count)) continue;
    ivec2 texel = ivec2(pixel.x, pixel.y + v * size.y);
    vec4 f = imageLoad(features, texel);
    penalty[v] = ulr_penalty(f, resolution_weight);
    if (penalty[v] < 0.0) continue;
    feather[v] = f.z;
    color[v] = imageLoad(warped, texel).rgb;
    seen = true;
  }
  vec4 result = vec4(0.0);
  float depth = 0.0;
  if (seen) {
    result = vec4(ulr_color(penalty, feather, color, best_views), 1.0);
    float z = imageLoad(fused_depth, pixel).r;
    depth = is_finite(z) && z > 0.0 ? z : 0.0;
  }
  imageStore(portrait, pixel, result);
  imageStore(portrait_depth, pixel, vec4(depth));
}
