#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// Warping and unstructured lumigraph blending in one pass (paper 3.1.1): each target pixel's
// surface point is sampled by every view (common/ibr_warp_sample.glsl) and blended
// (common/ulr_blend.glsl) in registers, so that no per-view atlas is written and read back.
// The result equals ibr_warp followed by ibr_blend, which stay for a learned blending that needs
// the atlases. Alpha is the coverage: 0 where no view sees the surface point, 1 where one does.
#include "shared/config.h"
#include "common/ibr_camera.glsl"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrWarpBlendPass, from WarpSettings and BlendSettings (passes/ibr_warp.h,
// passes/ibr_blend.h), where their defaults live: a kernel refuses to build while one is unset,
// so the initial values below are placeholders that GLSL requires, never used.
layout(constant_id = 0) const float visibility_tolerance_m = 0.0;
layout(constant_id = 1) const float visibility_tolerance_rel = 0.0;   // of the camera's depth
layout(constant_id = 2) const float feather_px = 0.0;                  // border band of the color image
layout(constant_id = 3) const int best_views = 0;                      // k
layout(constant_id = 4) const float resolution_weight = 0.0;           // radians of penalty per metre
// Views in the atlases' bands: a constant, so that the views past it cost nothing. llvmpipe runs
// every instruction for every group of invocations, whatever their mask.
layout(constant_id = 5) const int view_count = 0;

layout(binding = 0, r32f) uniform readonly image2D fused_depth;   // target view, 0 = nothing
layout(binding = 1, rgba8) uniform readonly image2D color;       // views stacked in bands
#define RT_BILINEAR_IMAGE color
#include "common/bilinear.glsl"
layout(binding = 2, rgba32f) uniform readonly image2D points;     // w: each view's own depth
#define RT_POINTS_IMAGE points
#include "common/view_sees.glsl"
#include "common/ibr_warp_sample.glsl"
#include "common/ulr_blend.glsl"
layout(binding = 3, rgba32f) uniform writeonly image2D portrait;        // straight color, alpha
layout(binding = 4, r32f) uniform writeonly image2D portrait_depth;     // metres, 0 = nothing
// The tiles with a surface (ibr_tiles, which zeroed the rest of the portrait): one workgroup each.
layout(std430, binding = 5) readonly buffer Tiles { uvec4 tiles[]; };

void main() {
  ivec2 size = imageSize(portrait);
  ivec2 pixel = ivec2(tiles[gl_WorkGroupID.x].xy * uvec2(RT_TILE_X, RT_TILE_Y) + gl_LocalInvocationID.xy);
  // No early return for the pixels past the edge: every load of the scene table below must come
  // before the first branch on the pixel (common/ibr_warp_sample.glsl says why).
  bool in_image = all(lessThan(pixel, size));
  float penalty[RT_IBR_MAX_VIEWS];  // -1: not a candidate
  float feather[RT_IBR_MAX_VIEWS];
  vec3 colors[RT_IBR_MAX_VIEWS];
  bool seen = false;
  vec3 eye = target_eye();
  float z = in_image ? imageLoad(fused_depth, pixel).r : 0.0;
  vec3 site = z > 0.0 ? target_surface_point(pixel, z) : vec3(0.0);
  // Unrolled, so that each view's index is a constant and its camera is loaded as a whole.
  [[unroll]] for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    IbrCamera camera = cameras[v];
    penalty[v] = -1.0;
    feather[v] = 0.0;
    colors[v] = vec3(0.0);
    if (v >= view_count || !(z > 0.0)) continue;
    WarpSample s = warp_sample_with(camera, eye, v, site, visibility_tolerance_m, visibility_tolerance_rel, feather_px);
    penalty[v] = ulr_penalty(s.features, resolution_weight);
    if (penalty[v] < 0.0) continue;
    feather[v] = s.features.z;
    colors[v] = s.color;
    seen = true;
  }
  if (!in_image) return;
  vec4 result = vec4(0.0);
  float depth = 0.0;
  if (seen) {
    result = vec4(ulr_color(penalty, feather, colors, best_views), 1.0);
    depth = is_finite(z) && z > 0.0 ? z : 0.0;
  }
  imageStore(portrait, pixel, result);
  imageStore(portrait_depth, pixel, vec4(depth));
}
