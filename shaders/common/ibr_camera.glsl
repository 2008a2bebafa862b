// Camera maths of the image-based model, mirrored line by line in passes/ibr_scene.cpp (the
// C++ references use that copy, so GPU and reference round the same way).
#ifndef REMOTETOUCH_IBR_CAMERA_GLSL
#define REMOTETOUCH_IBR_CAMERA_GLSL
#include "shared/config.h"

// Read as a uniform buffer by default: llvmpipe reads a uniform buffer at a constant offset once
// for all invocations, where no invocation is masked off. So those shaders read what they need
// of the table before their first branch on the pixel, with constant view indices (unrolled
// loops). A shader that indexes the cameras by a varying view (a loop counter, a dispatch's z)
// defines RT_IBR_SCENE_VARYING_VIEW first and reads it as a storage buffer, which llvmpipe
// gathers faster per invocation. The layout is the same in std140 as in std430: every member is
// a vec4 or a mat4.
#ifdef RT_IBR_SCENE_VARYING_VIEW
layout(std430, binding = 15) readonly buffer IbrSceneTable {
#else
layout(std140, binding = 15) uniform IbrSceneTable {
#endif
  IbrTarget target;
  IbrCamera cameras[RT_IBR_MAX_VIEWS];
};

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

vec3 transform_point(mat4 m, vec3 p) { return (m * vec4(p, 1.0)).xyz; }

// Inside the image, with `margin` pixels to spare (pixel centres at integers).
bool inside_image(vec2 pixel, vec2 size, float margin) {
  return all(greaterThanEqual(pixel, vec2(-0.5 + margin))) && all(lessThan(pixel, size - 0.5 - margin));
}

#endif
