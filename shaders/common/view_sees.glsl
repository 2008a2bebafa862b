// Warping's and refinement's visibility test, mirrored line by line by passes::view_sees.
#ifndef REMOTETOUCH_VIEW_SEES_GLSL
#define REMOTETOUCH_VIEW_SEES_GLSL

// The including shader names its rgba32f points atlas (w: each view's own depth, 0 = none) in
// RT_POINTS_IMAGE before including this file, as GLSL cannot pass a storage image.
// View `view` sees its camera-frame point at depth `z`, projected to `depth_pixel`, when its own
// depth at the nearest depth texel (bands of `depth_height` rows) is valid and within
// tolerance_m + tolerance_rel * that depth of z.
bool view_sees(int view, int depth_height, vec2 depth_pixel, float z, float tolerance_m, float tolerance_rel) {
  float own = imageLoad(RT_POINTS_IMAGE, ivec2(floor(depth_pixel + 0.5)) + ivec2(0, view * depth_height)).w;
  return own > 0.0 && abs(z - own) <= tolerance_m + tolerance_rel * own;
}

#endif
