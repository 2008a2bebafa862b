#pragma once
// Pass: rasterize simulated meshes (people, hands) from one camera.
//   in:  mesh (storage buffer of MeshVertex, a triangle list), face_texture (rgba32f, sampled
//        bilinearly, clamped: the head's photograph on vertices whose stripe period is negative,
//        see person_raster.frag; none = no face)
//   out: color rgba8 (shaded albedo, alpha 1 on surfaces), depth_m r32f (the camera's z in
//        metres, 0 where nothing is), part r32f (RT_PART_*), and a d32f depth buffer.
// The view is a pinhole camera (a site's RGBD camera, or the off-axis target view, which is a
// pinhole with a shifted principal point); lens distortion is not applied here.
#include <functional>
#include <span>

#include "geometry/camera.h"
#include "image/host_image.h"
#include "shared/config.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::MeshVertex;
using shader_abi::RasterViewParams;

// clip <- site for a pinhole camera, with OpenCV pixel centres (integers) mapped to Vulkan's
// (half-integers), and the near and far planes (metres).
RasterViewParams raster_view(const Camera& camera, double near_m, double far_m);

struct RasterTargets {
  vk::Image* color = nullptr;    // rgba8
  vk::Image* depth_m = nullptr;  // r32f
  vk::Image* part = nullptr;     // r32f
  vk::Image* depth_buffer = nullptr;  // d32f
};

class PersonRasterPass {
 public:
  explicit PersonRasterPass(vk::Context& context);
  // `face_texture`: the head's photograph; null draws heads in plain skin (a blank texture).
  void add_to(vk::FrameGraph& graph, vk::Buffer& mesh, std::function<uint32_t()> vertex_count,
              std::function<RasterViewParams()> view, const RasterTargets& targets,
              const std::string& pass_name = "person_raster", vk::Image* face_texture = nullptr) const;

 private:
  vk::GraphicsKernel kernel_;
  mutable vk::Image blank_face_;  // 1x1, alpha 0: the skin shows through; only ever read
  vk::Sampler sampler_;
};

// The plain C++ reference: a scanline-free edge-function rasterizer with near/far clipping,
// perspective-correct interpolation and a LESS depth test, as Vulkan specifies them, except
// for the rule that gives a pixel on a shared edge to one triangle only. `near_edge` marks
// pixels within one pixel of any drawn edge: only there may the GPU differ.
struct RasterReference {
  HostImage color, depth_m, part, near_edge;
};
// `face_texture` as the pass takes it (null: none).
RasterReference person_raster_reference(std::span<const MeshVertex> mesh, const RasterViewParams& view, uint32_t width,
                                        uint32_t height, const HostImage* face_texture = nullptr);

}  // namespace rt::passes
