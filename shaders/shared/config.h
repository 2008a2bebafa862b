// Shared by GLSL and C++: constants and the layouts of push-constant blocks. Only 4-byte scalars
// here, so that GLSL's push-constant (std430) layout and C++'s layout agree by construction.
#ifndef REMOTETOUCH_SHADER_CONFIG_H
#define REMOTETOUCH_SHADER_CONFIG_H

#ifdef __cplusplus
#include <array>
#include <cstdint>
#define RT_UINT std::uint32_t
#define RT_VEC4 std::array<float, 4>
#define RT_MAT4 std::array<float, 16> /* column-major, as GLSL's mat4 */
namespace rt::shader_abi {
#else
#define RT_UINT uint
#define RT_VEC4 vec4
#define RT_MAT4 mat4
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

// Surface kinds in the simulator's part mask.
#define RT_PART_NONE 0.0
#define RT_PART_BODY 1.0
#define RT_PART_HAND 2.0

// One vertex of a simulated mesh, pulled from a storage buffer (std430: four vec4).
struct MeshVertex {
  RT_VEC4 position_part;  // site-frame position (metres); w: RT_PART_* of its triangle
  RT_VEC4 normal_stripe;  // unit normal; w: stripe period along site y in metres, 0 = plain
  RT_VEC4 color;          // albedo, rgb in [0, 1]
  RT_VEC4 stripe_color;   // albedo of every other stripe
};

// A view for rasterization: clip <- site, and the row that gives the camera's z (metres along
// its optical axis), written to the linear-depth target.
struct RasterViewParams {
  RT_MAT4 clip_from_site;
  RT_VEC4 depth_row;  // z_camera = dot(depth_row.xyz, p) + depth_row.w
};

struct DepthSensorParams {
  RT_UINT seed;  // per camera and frame: the simulated noise is reproducible
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#undef RT_UINT
#endif
