#pragma once
// Pass: the fusion buffer resolved into the target view's depth, cracks filled
// (shaders/ibr_fuse.comp).
//   in:  the fusion buffer (ibr_splat)
//   out: fused_depth r32f, metres of the target camera's z, 0 = nothing.
// Min fusion takes the nearest depth; average fusion the mean of the depths that agree with it.
// An empty pixel takes its neighbours' mean when at least fill_min_neighbours of 8 are set and
// they lie within fill_tolerance_m of each other (never across a depth edge).
#include <cstdint>
#include <vector>

#include "passes/ibr_splat.h"

namespace rt::passes {

struct FuseSettings {
  DepthFusion fusion = DepthFusion::Min;
  int fill_min_neighbours = 5;
  float fill_tolerance_m = 0.03f;
};

class IbrFusePass {
 public:
  IbrFusePass(vk::Context& context, const FuseSettings& settings = {});
  void add_to(vk::FrameGraph& graph, vk::Buffer& fusion, vk::Image& fused_depth) const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage ibr_fuse_reference(const std::vector<uint32_t>& fusion, uint32_t width, uint32_t height,
                             const FuseSettings& settings = {});

}  // namespace rt::passes
