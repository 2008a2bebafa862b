#pragma once
// Pass: a depth camera's depth registered into its colour camera (shaders/depth_in_color.comp).
//   in:  depth_mm r16ui (millimetres, 0 = no measurement), the depth pixels' rays (a buffer from
//        depth_in_color_rays), the colour camera and colour_from_depth (push constants)
//   out: depth_in_color r16ui at the colour camera's size: millimetres along the colour camera's
//        z, the nearest surface where several land, 0 where none does
//   scratch: `nearest`, one uint per colour pixel (depth_in_color_nearest_desc)
// Three graph passes under one name: <name>_clear, <name> (the splat), <name>_resolve.
#include <Eigen/Geometry>

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "image/host_image.h"
#include "shared/depth_in_color.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct DepthInColorSettings {
  // Neighbouring depth pixels further apart than this (+ relative * the nearer depth) lie on two
  // surfaces and are not joined. A time-of-flight pixel of 1-2 mrad on a surface at 80 degrees
  // to the view steps about 2 cm at 2 m; a person before a wall steps tens of centimetres.
  float max_jump_m = 0.03f;
  float max_jump_relative = 0.02f;
  // A triangle wider or taller than this in the colour image is dropped: a surface seen edge-on
  // from one camera and face-on from the other, or a lens fold; never a real surface.
  float max_triangle_px = 64.0f;
};

// What the shader takes for one camera pair: colour_from_depth is rigid, in metres. Throws
// std::invalid_argument for an empty colour image or intrinsics that are not finite.
shader_abi::DepthInColorParams depth_in_color_params(const CameraIntrinsics& color,
                                                     const Eigen::Isometry3d& color_from_depth);

// The rays buffer's contents: (x/z, y/z) per depth pixel, row by row, two floats each.
std::vector<float> depth_in_color_rays(const CameraIntrinsics& depth);
vk::BufferDesc depth_in_color_rays_desc(uint32_t depth_width, uint32_t depth_height);
vk::BufferDesc depth_in_color_nearest_desc(uint32_t color_width, uint32_t color_height);

class DepthInColorPass {
 public:
  DepthInColorPass(vk::Context& context, const DepthInColorSettings& settings = {});
  // `params` is read when each frame is recorded; its colour size must stay the output's.
  void add_to(vk::FrameGraph& graph, vk::Image& depth_mm, vk::Buffer& rays, vk::Buffer& nearest,
              vk::Image& depth_in_color, std::function<shader_abi::DepthInColorParams()> params,
              const std::string& pass_name = "depth_in_color") const;

 private:
  DepthInColorSettings settings_;
  vk::ComputeKernel splat_;
  vk::ComputeKernel resolve_;
};

// The plain C++ reference: the output image (R16U, the colour camera's size).
HostImage depth_in_color_reference(const HostImage& depth_mm, std::span<const float> rays,
                                   const shader_abi::DepthInColorParams& params, const DepthInColorSettings& settings = {});

}  // namespace rt::passes
