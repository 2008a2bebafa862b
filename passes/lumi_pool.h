#pragma once
// Pass: Lumi-Net's cross-view pooling (shaders/lumi_pool.comp): after each view's C features, the
// mean and the maximum of each over the views that see the pixel (coverage > 0); 0 where none do.
//   in:  source tensor (views, C, h, w), coverage tensor (views, 1, h, w) (lumi_input)
//   out: result tensor (views, 3C, h, w): own, mean, max
#include <string>

#include "passes/common/lumi_tensor.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class LumiPoolPass {
 public:
  LumiPoolPass(vk::Context& context, uint32_t channels);
  uint32_t channels() const { return channels_; }
  void add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, vk::Buffer& coverage,
              vk::Buffer& result, uint32_t width, uint32_t height, uint32_t views) const;

 private:
  uint32_t channels_;
  vk::ComputeKernel kernel_;
};

LumiTensor lumi_pool_reference(const LumiTensor& source, const LumiTensor& coverage);

}  // namespace rt::passes
