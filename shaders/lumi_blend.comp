#version 460
#extension GL_GOOGLE_include_directive : require
// Lumi-Net's blend at the target's resolution: the upsampled weights, renormalised over the views
// that see this very pixel (upsampling spreads a view's weight past its silhouette, and a view
// that does not see the point has no color for it), times the warped colors; alpha the network's.
// Where the seeing views' weights are all 0 they share equally; where no view sees the point the
// portrait is empty (alpha 0, depth 0), as with the lumigraph blending. Never a NaN.
#include "shared/config.h"
#include "shared/lumi_net.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(binding = 0, r32f) uniform readonly image2D fused_depth;
layout(binding = 1, rgba32f) uniform readonly image2D warped;
layout(binding = 2, rgba32f) uniform readonly image2D features;
layout(std430, binding = 3) readonly buffer Blending { float blending[]; };  // (1, 1 + views, h, w)
layout(binding = 4, rgba32f) uniform writeonly image2D portrait;        // straight color, alpha
layout(binding = 5, r32f) uniform writeonly image2D portrait_depth;     // metres, 0 = nothing
layout(push_constant) uniform Push { LumiTensorParams params; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const ivec2 size = ivec2(params.width, params.height);
  if (any(greaterThanEqual(pixel, size))) return;
  const int plane = size.x * size.y, at = pixel.y * size.x + pixel.x;
  vec3 weighted = vec3(0.0), plain = vec3(0.0);
  float weight_sum = 0.0;
  int seeing = 0;
  for (int v = 0; v < int(params.views); ++v) {
    const ivec2 texel = ivec2(pixel.x, pixel.y + v * size.y);
    const vec4 f = imageLoad(features, texel);
    if (!(f.w > 0.0) || !(f.z > 0.0) || !is_finite(f.x) || !is_finite(f.y) || !is_finite(f.z)) continue;
    const vec3 color = unit_or_zero(imageLoad(warped, texel).rgb);
    const float raw = blending[(1 + v) * plane + at];
    const float w = is_finite(raw) ? max(raw, 0.0) : 0.0;
    weighted += w * color;
    plain += color;
    weight_sum += w;
    ++seeing;
  }
  vec4 result = vec4(0.0);
  float depth = 0.0;
  if (seeing > 0) {
    const vec3 color = weight_sum > 1e-6 ? weighted / weight_sum : plain / float(seeing);
    result = vec4(unit_or_zero(color), unit_or_zero(blending[at]));
    const float z = imageLoad(fused_depth, pixel).r;
    depth = is_finite(z) && z > 0.0 ? z : 0.0;
  }
  imageStore(portrait, pixel, result);
  imageStore(portrait_depth, pixel, vec4(depth));
}
