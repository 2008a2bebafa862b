#pragma once
// Pass: the geometry hand rasterized at `factor` x the target's resolution, resolved to it
// (shaders/hand_resolve.comp), so that its silhouette is antialiased where it meets the portrait.
//   in:  fine color rgba32f (straight), mask r32f (coverage), depth_m r32f (0 = no hand), at
//        (W * factor) x (H * factor)
//   out: color rgba32f (the mean of the covered samples, alpha 1 where any is covered), mask r32f
//        (the covered fraction), depth_m r32f (the nearest covered sample), at W x H
// Non-finite inputs: a mask counts as 0, a color channel as 0, a depth as no hand.
// ibr_resolve does the like for a portrait; the hand's layers differ in kind (a coverage mask of
// their own that the fusion reads, the nearest covered depth rather than a centre sample, any
// factor from 1), so they have their own pass rather than a portrait's rules.
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct HandLayerImages {
  vk::Image* color = nullptr;
  vk::Image* mask = nullptr;
  vk::Image* depth_m = nullptr;
};

class HandResolvePass {
 public:
  // factor: 1 to 4.
  HandResolvePass(vk::Context& context, uint32_t factor);
  void add_to(vk::FrameGraph& graph, const HandLayerImages& fine, const HandLayerImages& resolved,
              const std::string& pass_name = "hand_resolve") const;
  uint32_t factor() const { return factor_; }

 private:
  uint32_t factor_;
  vk::ComputeKernel kernel_;
};

// Throws unless 1 <= factor <= 4; returns it.
uint32_t check_hand_supersampling(uint32_t factor);

// The plain C++ reference.
struct HandLayers {
  HostImage color, mask, depth_m;
};
HandLayers hand_resolve_reference(const HostImage& fine_color, const HostImage& fine_mask, const HostImage& fine_depth_m,
                                  uint32_t factor);

}  // namespace rt::passes
