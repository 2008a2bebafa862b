// Shared by GLSL and C++: constants and the layouts of push-constant blocks. Only 4-byte scalars
// here, so that GLSL's push-constant (std430) layout and C++'s layout agree by construction.
#ifndef REMOTETOUCH_SHADER_CONFIG_H
#define REMOTETOUCH_SHADER_CONFIG_H

#ifdef __cplusplus
#include <cstdint>
#define RT_UINT std::uint32_t
namespace rt::shader_abi {
#else
#define RT_UINT uint
#endif

// Workgroup tile of the 2D image passes. 8x8 = 64 invocations: a multiple of every subgroup
// size we meet (lavapipe 8, NVIDIA 32, AMD 64).
#define RT_TILE_X 8
#define RT_TILE_Y 8

// Paper Eq. 4: the geometry hand fades in between these distances of the hand to the screen.
#define RT_FUSION_D_MIN_M 0.2
#define RT_FUSION_D_MAX_M 0.4

struct HandAlphaParams {
  // Distance in metres of the averaged hand joints to the screen; NaN or Inf means "no hand".
  float hand_distance_m;
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#undef RT_UINT
#endif
