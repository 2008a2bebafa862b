#version 460
#extension GL_GOOGLE_include_directive : require
// Warping (paper 3.1.1): every target pixel with a fused depth is a surface point; each view
// samples its color there (bilinear, through its lens) when its own depth image agrees that it
// sees that point (occluded or inconsistent samples rejected with a tolerance). Next to the
// color it writes what blending needs, so that a learned blending (Lumi-Net) can take the same
// inputs: the angle between the target ray and the camera ray at the point (Buehler et al.'s
// angle penalty), the resolution penalty, and a feather that falls to 0 at the image border.
#include "shared/config.h"
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
layout(binding = 3, rgba32f) uniform writeonly image2D warped;    // rgb, visible; bands of the target size
layout(binding = 4, rgba32f) uniform writeonly image2D features;  // angle (rad), resolution (m), feather, visible

void main() {
  int view = int(gl_GlobalInvocationID.z);
  ivec2 size = ivec2(target.size.xy);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  ivec2 out_texel = ivec2(pixel.x, pixel.y + view * size.y);
  vec4 sample_color = vec4(0.0);
  vec4 sample_features = vec4(0.0);
  float z = imageLoad(fused_depth, pixel).r;
  if (z > 0.0) {
    vec3 target_point = vec3((vec2(pixel) - target.pinhole.zw) / target.pinhole.xy * z, z);
    vec3 site = transform_point(target.site_from_camera, target_point);
    IbrCamera camera = cameras[view];
    vec3 q = transform_point(camera.camera_from_site, site);
    if (q.z > 1e-4) {
      vec2 color_size = lens_size(camera.color);
      vec2 depth_size = lens_size(camera.depth);
      vec2 color_pixel = lens_project(camera.color, q);
      vec2 depth_pixel = lens_project(camera.depth, q);
      // Tested in float before the conversion to integers, which is undefined far outside.
      if (inside_image(color_pixel, color_size, 0.0) && inside_image(depth_pixel, depth_size, 0.0)) {
        if (view_sees(view, int(depth_size.y), depth_pixel, q.z, visibility_tolerance_m, visibility_tolerance_rel)) {
          vec3 eye = transform_point(target.site_from_camera, vec3(0.0));
          vec3 centre = transform_point(camera.site_from_camera, vec3(0.0));
          vec3 to_eye = site - eye, to_camera = site - centre;
          float cosine = dot(to_eye, to_camera) / max(length(to_eye) * length(to_camera), 1e-12);
          float angle = acos(clamp(cosine, -1.0, 1.0));
          float resolution = max(0.0, length(to_camera) - length(to_eye));
          vec2 border = min(color_pixel + 0.5, color_size - 0.5 - color_pixel);
          // Never 0 inside the image: the feather shapes weights, not whether a view counts.
          float feather = clamp(min(border.x, border.y) / feather_px, 1e-3, 1.0);
          ivec2 color_band_size = ivec2(color_size);
          sample_color = vec4(bilinear_rgb(color_pixel, view * color_band_size.y, color_band_size), 1.0);
          sample_features = vec4(angle, resolution, feather, 1.0);
        }
      }
    }
  }
  imageStore(warped, out_texel, sample_color);
  imageStore(features, out_texel, sample_features);
}
