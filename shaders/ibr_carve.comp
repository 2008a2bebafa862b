#version 460
#extension GL_GOOGLE_include_directive : require
// See-through carving of the fused depth (free-space consistency): a fused surface point that a
// view looks straight through (its own depth there is farther, beyond warping's tolerance) is
// empty space, not a surface. This happens where the depth cameras are coarser than a gap: a
// finger gap is narrower than a depth pixel of most views, so the splats of the fingers cover it
// and the min-filter keeps them, while a view that looks along the gap sees the body behind it.
// Such a pixel takes the nearest surface behind it that a see-through view observes: the target
// ray marched onto that view's depth (its camera z is linear in the ray's z), kept only when some
// view sees that point, so that carving never uncovers a pixel.
// The see-through test probes the view's depth probe_texels of a texel around the projection, all
// four agreeing, so that a point that close to a depth edge (where the nearest texel may lie on
// the far side by rounding alone) is not carved.
#include "shared/config.h"
#include "common/numeric.glsl"
#define RT_IBR_SCENE_VARYING_VIEW
#include "common/ibr_camera.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrCarvePass, from CarveSettings (passes/ibr_carve.h) and VisibilityTolerance
// (passes/common/ibr_scene.h), where their defaults live: a kernel refuses to build while one is
// unset, so the initial values below are placeholders that GLSL requires, never used.
layout(constant_id = 0) const float visibility_tolerance_m = 0.0;
layout(constant_id = 1) const float visibility_tolerance_rel = 0.0;   // of the camera's depth
layout(constant_id = 2) const float probe_texels = 0.0;                // probe offset around the projection
layout(constant_id = 3) const int march_steps = 0;

layout(binding = 0, r32f) uniform readonly image2D fused_depth;    // target view, 0 = nothing
layout(binding = 1, rgba32f) uniform readonly image2D points;      // w: each view's own depth, 0 = none
#define RT_POINTS_IMAGE points
#include "common/view_sees.glsl"
layout(binding = 2, r32f) uniform writeonly image2D carved_depth;
layout(push_constant) uniform Push { IbrBlendParams params; };

// The view's own point at the depth texel nearest `depth_pixel`, clamped to the band.
vec4 own_point(int view, vec2 depth_pixel, ivec2 depth_size) {
  ivec2 texel = clamp(ivec2(floor(depth_pixel + 0.5)), ivec2(0), depth_size - 1);
  return imageLoad(points, texel + ivec2(0, view * depth_size.y));
}

bool farther(float own, float z) {
  return own > 0.0 && own > z + visibility_tolerance_m + visibility_tolerance_rel * own;
}

vec3 ray_point(vec2 ray, float z) { return transform_point(target.site_from_camera, vec3(ray * z, z)); }

// The target depth where the ray meets view `view`'s depth surface, from `z`; the last estimate
// if the ray leaves the view's image or valid depth on the way.
float march_onto_view(int view, vec2 ray, float z, ivec2 depth_size) {
  mat4 camera_from_site = cameras[view].camera_from_site;
  float at_eye = transform_point(camera_from_site, ray_point(ray, 0.0)).z;
  float per_metre = transform_point(camera_from_site, ray_point(ray, 1.0)).z - at_eye;
  if (!(abs(per_metre) > 1e-6)) return z;
  for (int step = 0; step < march_steps; ++step) {
    vec3 q = transform_point(camera_from_site, ray_point(ray, z));
    if (q.z <= 1e-4) break;
    vec2 depth_pixel = lens_project(cameras[view].depth, q);
    if (!inside_image(depth_pixel, vec2(depth_size), 0.0)) break;
    float own = own_point(view, depth_pixel, depth_size).w;
    if (!(own > 0.0)) break;
    z = (own - at_eye) / per_metre;
  }
  return z;
}

void main() {
  ivec2 size = imageSize(fused_depth);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  float z = imageLoad(fused_depth, pixel).r;
  float carved = 0.0;  // nothing there, also for a NaN, infinite or negative depth
  if (z > 0.0 && is_finite(z)) {
    carved = z;
    vec2 ray = (vec2(pixel) - target.pinhole.zw) / target.pinhole.xy;
    vec3 site = ray_point(ray, z);
    float behind = 0.0;  // the nearest surface behind that a see-through view observes
    for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
      if (v >= int(params.view_count)) break;
      vec3 q = transform_point(cameras[v].camera_from_site, site);
      if (q.z <= 1e-4) continue;
      ivec2 depth_size = ivec2(lens_size(cameras[v].depth));
      vec2 depth_pixel = lens_project(cameras[v].depth, q);
      if (!inside_image(depth_pixel, vec2(depth_size), 0.0)) continue;
      bool sees_through = true;
      for (int corner = 0; corner < 4; ++corner) {
        vec2 offset = vec2((corner & 1) == 0 ? -probe_texels : probe_texels, (corner & 2) == 0 ? -probe_texels : probe_texels);
        if (!farther(own_point(v, depth_pixel + offset, depth_size).w, q.z)) sees_through = false;
      }
      if (!sees_through) continue;
      float start = transform_point(target.camera_from_site, own_point(v, depth_pixel, depth_size).xyz).z;
      float surface = march_onto_view(v, ray, start, depth_size);
      if (surface > z && (behind == 0.0 || surface < behind)) behind = surface;
    }
    if (behind > z) {
      vec3 behind_site = ray_point(ray, behind);
      bool seen = false;
      for (int v = 0; v < RT_IBR_MAX_VIEWS; ++v) {
        if (v >= int(params.view_count)) break;
        vec3 q = transform_point(cameras[v].camera_from_site, behind_site);
        if (q.z <= 1e-4) continue;
        vec2 depth_size = lens_size(cameras[v].depth);
        vec2 depth_pixel = lens_project(cameras[v].depth, q);
        if (!inside_image(depth_pixel, depth_size, 0.0) ||
            !inside_image(lens_project(cameras[v].color, q), lens_size(cameras[v].color), 0.0))
          continue;
        if (view_sees(v, int(depth_size.y), depth_pixel, q.z, visibility_tolerance_m, visibility_tolerance_rel)) {
          seen = true;
          break;
        }
      }
      if (seen) carved = behind;
    }
  }
  imageStore(carved_depth, pixel, vec4(carved));
}
