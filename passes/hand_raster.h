#pragma once
// Pass: rasterize the skinned hand from the target view (the local eye's off-axis view through
// the screen), unlit and textured: the "projected-depth hand mask" of the fusion passes.
//   in:  skinned (SkinnedVertex[]), indices (uint triangle list), skin_texture (rgba32f, sampled
//        bilinearly, clamped)
//   out: color rgba32f (straight alpha: 1 on the hand), depth_m r32f (camera z in metres, 0 =
//        no hand), mask r32f (1 on the hand, 0 elsewhere), and a d32f depth buffer.
#include <Eigen/Core>
#include <functional>
#include <span>

#include "image/host_image.h"
#include "passes/person_raster.h"
#include "shared/config.h"
#include "shared/hand_shading.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::HandRasterParams;
using shader_abi::SkinnedVertex;

// The view with the shading coefficients (hand/shading_fit.h: raster_shading).
HandRasterParams hand_raster_params(const RasterViewParams& view, const std::array<std::array<float, 4>, 3>& shading);

struct HandRasterTargets {
  vk::Image* color = nullptr;         // rgba32f
  vk::Image* depth_m = nullptr;       // r32f
  vk::Image* mask = nullptr;          // r32f
  vk::Image* normal = nullptr;        // rgba32f
  vk::Image* depth_buffer = nullptr;  // d32f
};

class HandRasterPass {
 public:
  explicit HandRasterPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Buffer& skinned, vk::Buffer& indices, std::function<uint32_t()> index_count,
              vk::Image& texture, const vk::Sampler& sampler, std::function<HandRasterParams()> params,
              const HandRasterTargets& targets, const std::string& pass_name = "hand_raster") const;

 private:
  vk::GraphicsKernel kernel_;
};

// The plain C++ reference: the triangles through person_raster_reference (same clipping,
// depth test and edge rules) for depth and mask, the texture sampled bilinearly with clamping
// at the interpolated coordinates. `near_edge` marks pixels within one pixel of a silhouette,
// a texture seam or a clipped edge: only there may the GPU's tie-breaking differ.
struct HandRasterReference {
  HostImage color, depth_m, mask, normal, near_edge;
};
HandRasterReference hand_raster_reference(std::span<const SkinnedVertex> skinned, std::span<const uint32_t> indices,
                                          const HostImage& texture, const HandRasterParams& params, uint32_t width,
                                          uint32_t height);
// Bilinear texture lookup as Vulkan does it (unnormalised centre at +0.5, clamp to edge).
Eigen::Vector4f sample_bilinear(const HostImage& texture, float u, float v);

}  // namespace rt::passes
