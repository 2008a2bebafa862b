// OpenCV's camera model in GLSL, mirrored in passes/common/ibr_scene.cpp (lens_pixel), so that a
// pass and its C++ reference round the same way. A file of its own, apart from the image-based
// model's camera table, so that a pass with a camera of its own binds no table.
#ifndef REMOTETOUCH_LENS_GLSL
#define REMOTETOUCH_LENS_GLSL
#include "shared/config.h"

// Normalised image coordinates (x/z, y/z) to distorted pixel coordinates (OpenCV's model).
vec2 lens_pixel(IbrLens lens, vec2 xy) {
  float r2 = dot(xy, xy);
  float numerator = 1.0 + r2 * (lens.radial.x + r2 * (lens.radial.y + r2 * lens.radial.z));
  float denominator = 1.0 + r2 * (lens.rational.x + r2 * (lens.rational.y + r2 * lens.rational.z));
  float radial = numerator / denominator;
  float p1 = lens.tangential.x, p2 = lens.tangential.y;
  vec2 distorted = xy * radial + vec2(2.0 * p1 * xy.x * xy.y + p2 * (r2 + 2.0 * xy.x * xy.x),
                                      p1 * (r2 + 2.0 * xy.y * xy.y) + 2.0 * p2 * xy.x * xy.y);
  return lens.pinhole.xy * distorted + lens.pinhole.zw;
}

vec2 lens_size(IbrLens lens) { return lens.tangential.zw; }

// Pixel coordinates of a camera-frame point (z > 0 checked by the caller).
vec2 lens_project(IbrLens lens, vec3 p) { return lens_pixel(lens, p.xy / p.z); }

#endif
