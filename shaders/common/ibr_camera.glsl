// Camera maths of the image-based model, mirrored line by line in passes/ibr_scene.cpp (the
// C++ references use that copy, so GPU and reference round the same way).
#ifndef REMOTETOUCH_IBR_CAMERA_GLSL
#define REMOTETOUCH_IBR_CAMERA_GLSL
#include "shared/config.h"
#include "common/lens.glsl"

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

vec3 transform_point(mat4 m, vec3 p) { return (m * vec4(p, 1.0)).xyz; }

// Inside the image, with `margin` pixels to spare (pixel centres at integers).
bool inside_image(vec2 pixel, vec2 size, float margin) {
  return all(greaterThanEqual(pixel, vec2(-0.5 + margin))) && all(lessThan(pixel, size - 0.5 - margin));
}

#endif
