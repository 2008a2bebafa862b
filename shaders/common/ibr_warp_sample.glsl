// One view's sample of a target pixel's surface point (paper 3.1.1), shared by the split warp
// (whose per-view output a learned blending reads) and the fused warp-and-lumigraph-blend, so
// the two cannot drift apart. Mirrored line by line by passes::ibr_warp_reference.
#ifndef REMOTETOUCH_IBR_WARP_SAMPLE_GLSL
#define REMOTETOUCH_IBR_WARP_SAMPLE_GLSL

// The including shader includes common/ibr_camera.glsl, and common/bilinear.glsl and
// common/view_sees.glsl with their images named, before this file.

// What a view contributes to a target pixel: its color and the inputs of any blending (the
// angle between the target ray and the camera ray at the point in radians, Buehler et al.'s
// angle penalty; the resolution penalty in metres; a feather that falls to 0 at the image
// border; visible). All zero when the view does not see the point.
struct WarpSample {
  vec3 color;
  vec4 features;
};

// The site-frame surface point of target pixel `pixel` at target depth `z`.
vec3 target_surface_point(ivec2 pixel, float z) {
  vec3 target_point = vec3((vec2(pixel) - target.pinhole.zw) / target.pinhole.xy * z, z);
  return transform_point(target.site_from_camera, target_point);
}

// A view sees a surface point when it lies in front of the camera, projects inside its color
// and depth images, and its own depth there agrees within the tolerance.
// `camera` is cameras[view] and `eye` the target camera's centre in the site frame, passed in so
// that a caller can read them before its first branch on the pixel (common/ibr_camera.glsl says
// why).
WarpSample warp_sample_with(IbrCamera camera, vec3 eye, int view, vec3 site, float tolerance_m, float tolerance_rel,
                            float feather_px) {
  WarpSample result = WarpSample(vec3(0.0), vec4(0.0));
  vec3 q = transform_point(camera.camera_from_site, site);
  if (!(q.z > 1e-4)) return result;
  vec2 color_size = lens_size(camera.color);
  vec2 depth_size = lens_size(camera.depth);
  vec2 color_pixel = lens_project(camera.color, q);
  vec2 depth_pixel = lens_project(camera.depth, q);
  // Tested in float before the conversion to integers, which is undefined far outside.
  if (!inside_image(color_pixel, color_size, 0.0) || !inside_image(depth_pixel, depth_size, 0.0)) return result;
  if (!view_sees(view, int(depth_size.y), depth_pixel, q.z, tolerance_m, tolerance_rel)) return result;
  vec3 centre = transform_point(camera.site_from_camera, vec3(0.0));
  vec3 to_eye = site - eye, to_camera = site - centre;
  float cosine = dot(to_eye, to_camera) / max(length(to_eye) * length(to_camera), 1e-12);
  float angle = acos(clamp(cosine, -1.0, 1.0));
  float resolution = max(0.0, length(to_camera) - length(to_eye));
  vec2 border = min(color_pixel + 0.5, color_size - 0.5 - color_pixel);
  // Never 0 inside the image: the feather shapes weights, not whether a view counts.
  float feather = clamp(min(border.x, border.y) / feather_px, 1e-3, 1.0);
  ivec2 color_band_size = ivec2(color_size);
  result.color = bilinear_rgb(color_pixel, view * color_band_size.y, color_band_size);
  result.features = vec4(angle, resolution, feather, 1.0);
  return result;
}

vec3 target_eye() { return transform_point(target.site_from_camera, vec3(0.0)); }

WarpSample warp_sample(int view, vec3 site, float tolerance_m, float tolerance_rel, float feather_px) {
  return warp_sample_with(cameras[view], target_eye(), view, site, tolerance_m, tolerance_rel, feather_px);
}

#endif
