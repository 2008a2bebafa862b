#version 460
#extension GL_GOOGLE_include_directive : require
// Unstructured lumigraph blending (Buehler et al. 2001): each visible view's penalty is its
// angle penalty plus a weighted resolution penalty; the k-th smallest penalty is the threshold,
// so the k-1 best views get weight 1 - p / p_k (the k-th falls to zero and views fade in and out
// smoothly as the eye moves), times the field-of-view feather, normalised. With fewer than k
// visible views the threshold is just above the largest penalty. Alpha is the coverage: 0 where
// no view sees the surface point (never a NaN), 1 where one does; the feather only shapes weights.
#include "shared/config.h"
#include "common/numeric.glsl"

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
  int candidates = 0;
  float largest = 0.0;
  for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    penalty[v] = -1.0;
    feather[v] = 0.0;
    if (v >= int(params.view_count)) continue;
    vec4 f = imageLoad(features, ivec2(pixel.x, pixel.y + v * size.y));
    // Written so that NaN features count as not visible.
    if (!(f.w > 0.0) || !(f.z > 0.0) || !is_finite(f.x) || !is_finite(f.y) || !is_finite(f.z)) continue;
    penalty[v] = max(f.x, 0.0) + resolution_weight * max(f.y, 0.0);
    feather[v] = f.z;
    largest = max(largest, penalty[v]);
    ++candidates;
  }
  vec4 result = vec4(0.0);
  float depth = 0.0;
  if (candidates > 0) {
    float threshold = largest * 1.0001 + 1e-6;
    if (candidates >= best_views) {
      // The k-th smallest penalty: the one with exactly k-1 candidates strictly below it (ties
      // broken by index, so that equal penalties still count once each).
      for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
        if (penalty[v] < 0.0) continue;
        int below = 0;
        for (int u = 0; u < RT_IBR_MAX_VIEWS; ++u)
          if (penalty[u] >= 0.0 && (penalty[u] < penalty[v] || (penalty[u] == penalty[v] && u < v))) ++below;
        if (below == best_views - 1) threshold = penalty[v];
      }
    }
    vec3 color_sum = vec3(0.0);
    float weight_sum = 0.0, best_penalty = 1e30;
    vec3 best_color = vec3(0.0);
    for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
      if (penalty[v] < 0.0) continue;
      vec3 c = unit_or_zero(imageLoad(warped, ivec2(pixel.x, pixel.y + v * size.y)).rgb);
      float w = threshold > 0.0 ? max(0.0, 1.0 - penalty[v] / threshold) * feather[v] : feather[v];
      color_sum += w * c;
      weight_sum += w;
      if (penalty[v] < best_penalty) {
        best_penalty = penalty[v];
        best_color = c;
      }
    }
    // Every weight zero happens only when the best views tie with the threshold: take the best.
    vec3 color = weight_sum > 1e-6 ? color_sum / weight_sum : best_color;
    result = vec4(unit_or_zero(color), 1.0);
    float z = imageLoad(fused_depth, pixel).r;
    depth = is_finite(z) && z > 0.0 ? z : 0.0;
  }
  imageStore(portrait, pixel, result);
  imageStore(portrait_depth, pixel, vec4(depth));
}
