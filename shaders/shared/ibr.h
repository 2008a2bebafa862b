// Shared by GLSL and C++: the image-based model's camera table and the push constants of its
// passes (paper section 3.1.1). Only 4-byte scalars, vec4 and mat4, so that std430 and C++
// agree by construction.
#ifndef REMOTETOUCH_SHADER_IBR_H
#define REMOTETOUCH_SHADER_IBR_H

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

// Views one frame can use; the paper selects 4 of a site's 6 cameras.
#define RT_IBR_MAX_VIEWS 6

// An empty slot of the fusion buffer: above the bits of every positive float depth.
#define RT_IBR_EMPTY_DEPTH_BITS 0xffffffffu

// A pinhole with OpenCV's rational distortion; pixel centres at integer coordinates, as OpenCV.
struct IbrLens {
  RT_VEC4 pinhole;     // fx, fy, cx, cy
  RT_VEC4 radial;      // k1, k2, k3, 0: the numerator of the radial factor
  RT_VEC4 rational;    // k4, k5, k6, 0: its denominator
  RT_VEC4 tangential;  // p1, p2, width, height (pixels)
};

// One RGBD camera. Colour and depth share one pose (as the simulator's registered cameras do).
struct IbrCamera {
  RT_MAT4 camera_from_site;
  RT_MAT4 site_from_camera;
  IbrLens colour;
  IbrLens depth;
};

// The target view: an undistorted pinhole (geometry/target_view.h).
struct IbrTarget {
  RT_MAT4 camera_from_site;
  RT_MAT4 site_from_camera;
  RT_VEC4 pinhole;  // fx, fy, cx, cy
  RT_VEC4 size;     // width, height, 0, 0
};

struct IbrForegroundParams {
  RT_VEC4 volume_min;  // the user's volume in the site frame (metres); w unused
  RT_VEC4 volume_max;
};

struct IbrBlendParams {
  RT_UINT view_count;  // bands filled in the atlases
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#undef RT_UINT
#undef RT_VEC4
#undef RT_MAT4
#endif
