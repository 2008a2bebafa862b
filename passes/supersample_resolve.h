#pragma once
// Pass: a view rendered at `factor` x the resolution resolved to its own (shaders/supersample_resolve.comp).
//   in:  fine color rgba8, depth_m r32f, part r32f at (W * factor) x (H * factor)
//   out: color rgba8 (box mean of the factor x factor samples), depth_m and part (the centre
//        sample, on the pixel's centre since factor is odd), at W x H.
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct ResolveImages {
  vk::Image* color = nullptr;
  vk::Image* depth_m = nullptr;
  vk::Image* part = nullptr;
};

class SupersampleResolvePass {
 public:
  // factor: odd, 1..7.
  SupersampleResolvePass(vk::Context& context, uint32_t factor);
  void add_to(vk::FrameGraph& graph, const ResolveImages& fine, const ResolveImages& resolved,
              const std::string& pass_name = "supersample_resolve") const;
  uint32_t factor() const { return factor_; }

 private:
  uint32_t factor_;
  vk::ComputeKernel kernel_;
};

// The plain C++ reference of one image: box mean for rgba8, centre sample for r32f.
HostImage supersample_resolve_reference(const HostImage& fine, uint32_t factor);

}  // namespace rt::passes
