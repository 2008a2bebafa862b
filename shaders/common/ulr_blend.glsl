// Unstructured lumigraph blending (Buehler et al. 2001) of one target pixel's views, shared by
// the split blend (ibr_blend, from the warp's atlases) and the fused warp-and-blend, so the two
// cannot drift apart. Mirrored line by line by passes::ibr_blend_reference.
#ifndef REMOTETOUCH_ULR_BLEND_GLSL
#define REMOTETOUCH_ULR_BLEND_GLSL
#include "shared/config.h"
#include "common/numeric.glsl"

// The including shader enables GL_EXT_control_flow_attributes: the loops over the views are
// unrolled so that the per-view arrays stay in registers (llvmpipe keeps an array indexed by a
// loop counter in memory, one copy per invocation).

// A view's penalty from its warp features (angle, resolution, feather, visible): its angle
// penalty plus a weighted resolution penalty, or -1 when it is no candidate. Written so that
// NaN features count as not visible.
float ulr_penalty(vec4 f, float resolution_weight) {
  if (!(f.w > 0.0) || !(f.z > 0.0) || !is_finite(f.x) || !is_finite(f.y) || !is_finite(f.z)) return -1.0;
  return max(f.x, 0.0) + resolution_weight * max(f.y, 0.0);
}

// The blended color of the candidates (penalty >= 0; at least one). The k-th smallest penalty
// is the threshold, so the k-1 best views get weight 1 - p / p_k (the k-th falls to zero and
// views fade in and out smoothly as the eye moves), times the field-of-view feather,
// normalised. With fewer than k candidates the threshold is just above the largest penalty.
vec3 ulr_color(float penalty[RT_IBR_MAX_VIEWS], float feather[RT_IBR_MAX_VIEWS], vec3 color[RT_IBR_MAX_VIEWS],
               int best_views) {
  int candidates = 0;
  float largest = 0.0;
  [[unroll]] for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v)
    if (penalty[v] >= 0.0) {
      largest = max(largest, penalty[v]);
      ++candidates;
    }
  float threshold = largest * 1.0001 + 1e-6;
  if (candidates >= best_views) {
    // The k-th smallest penalty: the one with exactly k-1 candidates strictly below it (ties
    // broken by index, so that equal penalties still count once each).
    [[unroll]] for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
      if (penalty[v] < 0.0) continue;
      int below = 0;
      [[unroll]] for (int u = 0; u < RT_IBR_MAX_VIEWS; ++u)
        if (penalty[u] >= 0.0 && (penalty[u] < penalty[v] || (penalty[u] == penalty[v] && u < v))) ++below;
      if (below == best_views - 1) threshold = penalty[v];
    }
  }
  vec3 color_sum = vec3(0.0);
  float weight_sum = 0.0, best_penalty = 1e30;
  vec3 best_color = vec3(0.0);
  [[unroll]] for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    if (penalty[v] < 0.0) continue;
    vec3 c = unit_or_zero(color[v]);
    float w = threshold > 0.0 ? max(0.0, 1.0 - penalty[v] / threshold) * feather[v] : feather[v];
    color_sum += w * c;
    weight_sum += w;
    if (penalty[v] < best_penalty) {
      best_penalty = penalty[v];
      best_color = c;
    }
  }
  // Every weight zero happens only when the best views tie with the threshold: take the best.
  return unit_or_zero(weight_sum > 1e-6 ? color_sum / weight_sum : best_color);
}

#endif
