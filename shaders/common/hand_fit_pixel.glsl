// Appearance adaption's pixels (paper Eq. 3): where the mesh covers, the portrait has alpha over
// one half, both depths are valid and agree within the tolerance, and neither color is black or
// saturated in any channel (those carry no color). The color statistics and the shading estimate
// fit over the same pixels.
#ifndef REMOTETOUCH_HAND_FIT_PIXEL_GLSL
#define REMOTETOUCH_HAND_FIT_PIXEL_GLSL

#include "common/numeric.glsl"

bool hand_fit_usable(vec3 c, ColorStatsParams p) {
  return is_finite(c.x) && is_finite(c.y) && is_finite(c.z) && all(greaterThan(c, vec3(p.min_level))) &&
         all(lessThan(c, vec3(p.max_level)));
}

bool hand_fit_pixel(vec4 image, float image_depth_m, vec4 mesh, float mesh_depth_m, float mesh_coverage,
                    ColorStatsParams p) {
  return mesh_coverage > 0.5 && image.a > 0.5 && is_finite(image_depth_m) && is_finite(mesh_depth_m) &&
         image_depth_m > 0.0 && mesh_depth_m > 0.0 && abs(image_depth_m - mesh_depth_m) < p.depth_tolerance_m &&
         hand_fit_usable(image.rgb, p) && hand_fit_usable(mesh.rgb, p);
}

#endif
