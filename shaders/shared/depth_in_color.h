// Shared by GLSL and C++: the depth_in_color pass's layout and constants (a camera's depth
// registered into its colour camera). Kept out of config.h, as hand_shading.h is, so that the
// pass's ABI can change without rebuilding every pass; IbrLens and RT_VEC4 come from config.h.
#ifndef REMOTETOUCH_SHADER_DEPTH_IN_COLOR_H
#define REMOTETOUCH_SHADER_DEPTH_IN_COLOR_H
#include "shared/config.h"

#ifdef __cplusplus
namespace rt::shader_abi {
#endif

// An empty slot of the nearest-depth buffer: above every millimetre value.
#define RT_DEPTH_IN_COLOR_EMPTY 0xffffffffu
// Nearer than this to the colour camera (metres) counts as behind it.
#define RT_DEPTH_IN_COLOR_NEAR_M 0.001

struct DepthInColorParams {
  RT_VEC4 color_from_depth[3];  // rows of the rigid [R | t], metres
  IbrLens color;                // the colour camera; its width and height are the output's
  RT_VEC4 field;                // x: the largest x^2 + y^2 (z = 1) the colour lens maps; y, z, w unused
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#endif
