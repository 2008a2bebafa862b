#pragma once
// What every pass of the image-based model shares: the camera table (the target view and the
// selected RGBD cameras, shaders/shared/ibr.h) in a host-visible storage buffer rewritten each
// frame, the per-pixel rays of the depth cameras, and the views-in-bands layout of the atlases
// (view v occupies rows [v * height, (v + 1) * height)). Also the float camera maths of
// shaders/common/ibr_camera.glsl, for the C++ references.
#include <array>
#include <span>
#include <vector>

#include "geometry/camera.h"
#include "image/host_image.h"
#include "shared/config.h"
#include "vulkan/resources.h"

namespace rt::passes {

// One RGBD camera: color and depth images with one pose (camera_from_site of `color`).
struct IbrCameraModel {
  Camera color;
  Camera depth;
};

struct IbrSceneTable {
  shader_abi::IbrTarget target{};
  std::array<shader_abi::IbrCamera, RT_IBR_MAX_VIEWS> cameras{};
  uint32_t camera_count = 0;
};

// Throws (std::invalid_argument) when there are no cameras or more than RT_IBR_MAX_VIEWS, the
// cameras' color or depth images differ in size, or color and depth poses differ.
IbrSceneTable make_scene_table(const Camera& target, std::span<const IbrCameraModel> cameras);

class IbrSceneBuffer {
 public:
  explicit IbrSceneBuffer(vk::Context& context);
  void write(const IbrSceneTable& table);  // between frames (the graph waits for the GPU)
  vk::Buffer& buffer() { return buffer_; }

 private:
  vk::Buffer buffer_;
};

// rgba32f, the cameras' depth images in bands: (d, 1) of each pixel's undistorted ray in the site
// frame, d = R (x/z, y/z, 1) with R the camera's rotation, so that the pixel's point at camera
// depth z is the camera's position plus z d; (0, 0, 0, 0) where undistortion fails.
HostImage depth_ray_atlas(std::span<const IbrCameraModel> cameras);

// Stacks same-sized images into bands, in order.
HostImage stack_bands(std::span<const HostImage> images);
HostImage band_of(const HostImage& atlas, uint32_t band, uint32_t band_height);

// The shader's maths in float, operation for operation.
struct Float2 { float x = 0, y = 0; };
struct Float3 { float x = 0, y = 0, z = 0; };
Float3 transform_point(const std::array<float, 16>& column_major, Float3 p);
Float2 lens_pixel(const shader_abi::IbrLens& lens, Float2 xy);
Float2 lens_project(const shader_abi::IbrLens& lens, Float3 p);
bool inside_image(Float2 pixel, Float2 size, float margin);
float length(Float3 v);
// Bilinear rgb of band `band` of an rgba8 atlas at pixel coordinates `at`, clamped to the band.
std::array<float, 3> bilinear_rgb(const HostImage& atlas, Float2 at, uint32_t band_row, uint32_t width, uint32_t height);
// The per-view visibility test of warping and refinement (one setting, WarpSettings::visibility,
// serves both): a view sees a surface point when its own depth at the point's nearest depth texel
// is valid and within metres + relative * that depth of the point's depth in that camera.
struct VisibilityTolerance {
  float metres = 0.03f;
  float relative = 0.01f;  // of the camera's own depth
  bool valid() const { return metres >= 0.0f && relative >= 0.0f; }  // false for NaN too
};
// View `view` sees its camera-frame point at depth `z`, projected to `depth_pixel`; its own depth
// is w of the `points` atlas (bands of `depth_height` rows).
bool view_sees(const HostImage& points, uint32_t view, uint32_t depth_height, Float2 depth_pixel, float z,
               VisibilityTolerance tolerance);

}  // namespace rt::passes
