#pragma once
// Pass: a portrait rendered at `factor` x the target's resolution resolved to the target
// (shaders/ibr_resolve.comp), so that its silhouettes carry partial alpha and its texture is
// filtered over each pixel, as the cameras' pixels and the ground truth are.
//   in:  fine portrait rgba32f (straight color, alpha), fine depth r32f, (W * factor) x (H * factor)
//   out: portrait rgba32f (straight color; alpha the mean coverage; color the premultiplied
//        mean over the covered samples), portrait depth r32f (the centre sample's, else the
//        nearest other sample's, 0 = nothing)
#include <cstdint>

#include "passes/ibr_blend.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class IbrResolvePass {
 public:
  // factor: 2..4.
  IbrResolvePass(vk::Context& context, uint32_t factor);
  void add_to(vk::FrameGraph& graph, vk::Image& fine_portrait, vk::Image& fine_depth, vk::Image& portrait,
              vk::Image& portrait_depth) const;
  uint32_t factor() const { return factor_; }

 private:
  uint32_t factor_;
  vk::ComputeKernel kernel_;
};

// The plain C++ reference.
Portrait ibr_resolve_reference(const HostImage& fine_portrait, const HostImage& fine_depth, uint32_t factor);

}  // namespace rt::passes
