#pragma once
// Pass: Lumi-Net's blending weights and alpha from its head (shaders/lumi_softmax.comp): a softmax
// of the weight logits over the views that see the pixel (coverage > 0), alpha the logistic of the
// mean alpha logit over them. No view seeing gives weights 0 and alpha 0; NaN and -Inf logits
// leave the softmax (all of them out: equal weights); a NaN alpha logit gives alpha 0. Never NaN.
//   in:  logits tensor (views, 2, h, w): weight logit, alpha logit; coverage (views, 1, h, w)
//   out: blending tensor (1, 1 + views, h, w): alpha, then each view's weight
#include "passes/common/lumi_tensor.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class LumiSoftmaxPass {
 public:
  explicit LumiSoftmaxPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Buffer& logits, vk::Buffer& coverage, vk::Buffer& blending, uint32_t width,
              uint32_t height, uint32_t views) const;

 private:
  vk::ComputeKernel kernel_;
};

LumiTensor lumi_softmax_reference(const LumiTensor& logits, const LumiTensor& coverage);

}  // namespace rt::passes
