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
// Workgroup of the passes that touch each pixel once and nothing around it: a run of pixels
// along one row, so that each workgroup streams contiguous memory. llvmpipe streams square tiles
// worse, and a GPU coalesces a row as well.
#define RT_ROW_X 256

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
  RT_VEC4 normal_stripe;  // unit normal; w: stripe period along site y in metres, 0 = plain; negative: a head vertex with face-texture coordinates
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


// ---- The geometry hand ----
// Bones of the hand template, in the tracker's hierarchy: arm, wrist, then per digit (thumb to
// pinky) metacarpal, proximal, intermediate, distal. Bone 2 + 4 digit + b.
#define RT_HAND_BONES 22

// A vertex of the hand template in its rest pose (std430: four vec4).
struct HandVertex {
  RT_VEC4 position_u;  // rest position in the template's frame (metres); w: texture u
  RT_VEC4 normal_v;    // unit normal; w: texture v
  RT_VEC4 joints;      // up to four bone indices (small integers as floats)
  RT_VEC4 weights;     // their weights: >= 0, summing to 1
};

// A skinned vertex, in the site frame.
struct SkinnedVertex {
  RT_VEC4 position_u;  // xyz metres; w: texture u
  RT_VEC4 normal_v;    // xyz unit normal; w: texture v
};

struct HandSkinParams {
  RT_UINT vertex_count;
};

// Paper Eq. 3 statistics: per workgroup partial sums of L, alpha, beta, their squares and the count.
#define RT_COLOR_STATS_GROUP 256
// Each invocation first sums this many pixels on its own: fewer workgroups, fewer barriers.
#define RT_COLOR_STATS_PIXELS_PER_THREAD 16
// Depth agreement of the image-based and the mesh hand for the statistics (DESIGN.md section 3).
#define RT_APPEARANCE_DEPTH_TOLERANCE_M 0.05

struct ColorStatsParams {
  RT_UINT pixel_count;      // width * height
  RT_UINT width;
  float depth_tolerance_m;  // |D_i - D_g| below this
  float min_level;          // pixels with a channel at or below this are black: skipped
  float max_level;          // ... at or above this are saturated: skipped
};

// One workgroup's sums over its valid pixels (L, alpha, beta in xyz; w unused).
struct ColorStatsPartial {
  RT_VEC4 count;  // x: pixels
  RT_VEC4 image_sum;
  RT_VEC4 image_sum_sq;
  RT_VEC4 mesh_sum;
  RT_VEC4 mesh_sum_sq;
};

// The smoothed statistics the texture transfer uses (L, alpha, beta in xyz).
struct AppearanceState {
  RT_VEC4 header;  // x: 1 once statistics exist, y: frames fitted so far, z: pixels in the last frame
  RT_VEC4 image_mean;
  RT_VEC4 image_sigma;
  RT_VEC4 mesh_mean;
  RT_VEC4 mesh_sigma;
};

struct ColorTransferParams {
  float sigma_floor;
};

struct ColorStatsReduceParams {
  RT_UINT group_count;     // partial sums to add
  float min_pixels;        // fewer pixels: keep the previous transfer
  float smoothing;         // least weight of a new frame (the first 1 / smoothing: running mean), (0, 1]
  float sigma_floor;       // floor on the template's standard deviation per channel
};

// The image-based model (paper 3.1.1): its camera table and push constants.
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

// One RGBD camera. Color and depth share one pose (as the simulator's registered cameras do).
struct IbrCamera {
  RT_MAT4 camera_from_site;
  RT_MAT4 site_from_camera;
  IbrLens color;
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

// The window's debug views (shaders/display_view.comp): which band of the source image shows,
// how its values map to gray or color, fitted into the window with its aspect kept.
#define RT_VIEW_COLOR 0u    // rgb as it is
#define RT_VIEW_DEPTH 1u    // metres in [low, high] to white..black; 0 or less: no depth
#define RT_VIEW_CHANNEL 2u  // one channel in [low, high] to black..white
struct DisplayViewParams {
  RT_UINT mode;
  RT_UINT channel;
  RT_UINT band_y0;      // the source rows shown: [band_y0, band_y0 + band_height)
  RT_UINT band_height;
  float low;
  float high;
};

// The benchmarks' roofline kernels (shaders/buffer_copy.comp, shaders/fma_peak.comp).
struct BufferCopyParams {
  RT_UINT count;  // uvec4 elements to copy
};
#define RT_FMA_CHAINS 8  // independent vec4 chains per invocation: enough to hide FMA latency
struct FmaPeakParams {
  RT_UINT invocations;
  RT_UINT iterations;  // per chain; each is one vec4 fused multiply-add (8 FLOPs)
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#undef RT_UINT
#endif
