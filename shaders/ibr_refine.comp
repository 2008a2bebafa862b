#version 460
#extension GL_GOOGLE_include_directive : require
// Optional refinement (the paper refines with a multi-view-stereo network; this is the classic
// plane sweep in its place): around each fused depth, `hypotheses` depths `step_m` apart are
// scored by how well the views' colors agree there (their variance, over the views that see the
// point: inside their images, their own depth agreeing as in warping, so that a view whose line
// of sight a hand blocks does not score the hand's color); the best-scoring depth wins, ties
// going to the fused depth.
#include "shared/config.h"
#define RT_IBR_SCENE_VARYING_VIEW
#include "common/ibr_camera.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrRefinePass, from RefineSettings (passes/ibr_refine.h) and
// VisibilityTolerance (passes/common/ibr_scene.h), where their defaults live: a kernel refuses to
// build while one is unset, so the initial values below are placeholders that GLSL requires, never
// used.
layout(constant_id = 0) const int hypotheses = 0;
layout(constant_id = 1) const float step_m = 0.0;
layout(constant_id = 2) const float visibility_tolerance_m = 0.0;
layout(constant_id = 3) const float visibility_tolerance_rel = 0.0;   // of the camera's depth

layout(binding = 0, r32f) uniform readonly image2D fused_depth;
layout(binding = 1, rgba8) uniform readonly image2D color;  // views stacked in bands
#define RT_BILINEAR_IMAGE color
#include "common/bilinear.glsl"
layout(binding = 2, r32f) uniform writeonly image2D refined_depth;
layout(binding = 3, rgba32f) uniform readonly image2D points;  // w: each view's own depth
#define RT_POINTS_IMAGE points
#include "common/view_sees.glsl"
layout(push_constant) uniform Push { IbrBlendParams params; };

// Color variance across the views that see `site`; -1 with fewer than two.
float disagreement(vec3 site) {
  vec3 sum = vec3(0.0), sum_squares = vec3(0.0);
  int seen = 0;
  for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
    if (v >= int(params.view_count)) break;
    vec3 q = transform_point(cameras[v].camera_from_site, site);
    if (q.z <= 1e-4) continue;
    vec2 at = lens_project(cameras[v].color, q);
    vec2 size = lens_size(cameras[v].color);
    vec2 depth_size = lens_size(cameras[v].depth);
    vec2 depth_pixel = lens_project(cameras[v].depth, q);
    if (!inside_image(at, size, 0.0) || !inside_image(depth_pixel, depth_size, 0.0)) continue;
    if (!view_sees(v, int(depth_size.y), depth_pixel, q.z, visibility_tolerance_m, visibility_tolerance_rel)) continue;
    vec3 c = bilinear_rgb(at, v * int(size.y), ivec2(size));
    sum += c;
    sum_squares += c * c;
    ++seen;
  }
  if (seen < 2) return -1.0;
  vec3 mean = sum / float(seen);
  vec3 variance = max(sum_squares / float(seen) - mean * mean, vec3(0.0));
  return variance.r + variance.g + variance.b;
}

void main() {
  ivec2 size = imageSize(fused_depth);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  float z = imageLoad(fused_depth, pixel).r;
  float best_z = z;
  if (z > 0.0) {
    vec2 ray = (vec2(pixel) - target.pinhole.zw) / target.pinhole.xy;
    float best_score = 1e30;
    float best_offset = 1e30;
    for (int h = 0; h < hypotheses; ++h) {
      float offset = (float(h) - 0.5 * float(hypotheses - 1)) * step_m;
      float candidate = z + offset;
      if (candidate <= 1e-3) continue;
      float score = disagreement(transform_point(target.site_from_camera, vec3(ray * candidate, candidate)));
      if (score < 0.0) continue;
      if (score < best_score || (score == best_score && abs(offset) < best_offset)) {
        best_score = score;
        best_offset = abs(offset);
        best_z = candidate;
      }
    }
  }
  imageStore(refined_depth, pixel, vec4(best_z));
}
