#version 460
#extension GL_GOOGLE_include_directive : require
// Warping (paper 3.1.1): every target pixel with a fused depth is a surface point; each view
// samples its color there (bilinear, through its lens) when its own depth image agrees that it
// sees that point (occluded or inconsistent samples rejected with a tolerance). Next to the
// color it writes what blending needs, so that a learned blending (Lumi-Net) can take the same
// inputs (common/ibr_warp_sample.glsl). The lumigraph blending skips these atlases: it runs
// fused with the warp (ibr_warp_blend).
#include "shared/config.h"
#define RT_IBR_SCENE_VARYING_VIEW
#include "common/ibr_camera.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrWarpPass, from WarpSettings (passes/ibr_warp.h) and VisibilityTolerance
// (passes/common/ibr_scene.h), where their defaults live: a kernel refuses to build while one is
// unset, so the initial values below are placeholders that GLSL requires, never used.
layout(constant_id = 0) const float visibility_tolerance_m = 0.0;
layout(constant_id = 1) const float visibility_tolerance_rel = 0.0;   // of the camera's depth
layout(constant_id = 2) const float feather_px = 0.0;                  // border band of the color image

layout(binding = 0, r32f) uniform readonly image2D fused_depth;   // target view, 0 = nothing
layout(binding = 1, rgba8) uniform readonly image2D color;       // views stacked in bands
#define RT_BILINEAR_IMAGE color
#include "common/bilinear.glsl"
layout(binding = 2, rgba32f) uniform readonly image2D points;     // w: each view's own depth
#define RT_POINTS_IMAGE points
#include "common/view_sees.glsl"
#include "common/ibr_warp_sample.glsl"
layout(binding = 3, rgba32f) uniform writeonly image2D warped;    // rgb, visible; bands of the target size
layout(binding = 4, rgba32f) uniform writeonly image2D features;  // angle (rad), resolution (m), feather, visible

void main() {
  int view = int(gl_GlobalInvocationID.z);
  ivec2 size = ivec2(target.size.xy);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  ivec2 out_texel = ivec2(pixel.x, pixel.y + view * size.y);
  WarpSample s = WarpSample(vec3(0.0), vec4(0.0));
  float z = imageLoad(fused_depth, pixel).r;
  if (z > 0.0)
    s = warp_sample(view, target_surface_point(pixel, z), visibility_tolerance_m, visibility_tolerance_rel, feather_px);
  imageStore(warped, out_texel, vec4(s.color, s.features.w));
  imageStore(features, out_texel, s.features);
}
