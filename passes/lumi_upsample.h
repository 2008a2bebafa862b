#pragma once
// Pass: bilinear upsampling of Lumi-Net's blending tensor to the target's resolution
// (shaders/lumi_upsample.comp), half-pixel centres as PyTorch's interpolate(align_corners=False)
// and ONNX's Resize, cropped to width x height.
//   in:  small tensor (1, planes, ceil(h / scale), ceil(w / scale))
//   out: full tensor (1, planes, h, w)
#include "passes/common/lumi_tensor.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class LumiUpsamplePass {
 public:
  explicit LumiUpsamplePass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Buffer& small, vk::Buffer& full, uint32_t width, uint32_t height,
              uint32_t planes, uint32_t scale) const;

 private:
  vk::ComputeKernel kernel_;
};

LumiTensor lumi_upsample_reference(const LumiTensor& small, uint32_t width, uint32_t height, uint32_t scale);

}  // namespace rt::passes
