// Shared by GLSL and C++: the geometry hand's shading, which appearance adaption estimates from
// the portrait (hand/shading_fit.h). The template's texture is albedo; the remote cameras see
// the hand lit. The shading is a function of the mesh's unit normal n in the remote site's frame,
// sum_k c_k b_k(n), over the nine real spherical harmonics of bands 0-2 (up to constants, which
// the coefficients absorb), the basis in which irradiance from distant light is smooth:
//   b(n) = (1, nx, ny, nz, nx ny, nx nz, ny nz, nx^2 - ny^2, 3 nz^2 - 1).
// Kept out of config.h so that the estimate's ABI can change without rebuilding every pass.
#ifndef REMOTETOUCH_SHADER_HAND_SHADING_H
#define REMOTETOUCH_SHADER_HAND_SHADING_H

#include "shared/config.h"

#ifdef __cplusplus
namespace rt::shader_abi {
#endif

#define RT_SHADING_TERMS 9
// Upper triangle of the normal equations' matrix, row by row: sum b_i b_j for i <= j.
#define RT_SHADING_MATRIX_TERMS 45
// Per workgroup: the pixel count, the matrix terms, then sum b_k y (y: the portrait's brightness
// over the template's), 55 floats padded to 14 vec4.
#define RT_SHADING_SUM_TERMS 55
#define RT_SHADING_PARTIAL_VEC4S 14
// The stats pass's workgroup and the pixels each invocation sums first (4096 a group, as Eq. 3's
// statistics); its tree reduction keeps every term of every invocation in shared memory:
// 55 x 64 floats, 14 KiB.
#define RT_SHADING_STATS_GROUP 64
#define RT_SHADING_STATS_PIXELS_PER_THREAD 64
// The shading the raster applies is clamped to this range: the estimate extrapolates over normals
// the fit never saw, and a shade that turns the hand black or white there is worse than none.
#define RT_HAND_SHADE_MIN 0.2
#define RT_HAND_SHADE_MAX 2.0

struct ShadingPartial {
  RT_VEC4 sums[RT_SHADING_PARTIAL_VEC4S];  // term t at sums[t / 4][t % 4]
};

// The hand raster's push constants: the view and the shading coefficients c_0..c_8 (c_9..c_11
// unused). Unlit is c = (1, 0, ..., 0). 128 bytes: the least push-constant size Vulkan promises.
struct HandRasterParams {
  RasterViewParams view;
  RT_VEC4 shading[3];
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#endif
