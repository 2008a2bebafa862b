#pragma once
// Pass: one convolution layer of Lumi-Net with its bias and optional ReLU fused
// (shaders/lumi_conv.comp): 3x3 or 1x1, zero padding, the same weights for every view.
//   in:  source tensor (views, in_channels, height, width), parameter buffer (the layer's weights
//        in PyTorch's order (out, in, ky, kx), then its bias, from a float offset)
//   out: result tensor (views, out_channels, height, width)
// Channel counts and the kernel size are specialization constants: one kernel per layer shape.
#include <cstddef>
#include <span>
#include <string>

#include "passes/common/lumi_tensor.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct LumiConvShape {
  uint32_t in_channels = 1;
  uint32_t out_channels = 1;
  uint32_t kernel_size = 3;  // 1 or 3
  bool relu = true;

  size_t parameter_count() const { return size_t(out_channels) * in_channels * kernel_size * kernel_size + out_channels; }
};

class LumiConvPass {
 public:
  LumiConvPass(vk::Context& context, const LumiConvShape& shape);
  const LumiConvShape& shape() const { return shape_; }
  // `name` names the pass in the graph (a network has several layers).
  void add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, vk::Buffer& parameters,
              size_t weight_offset, vk::Buffer& result, uint32_t width, uint32_t height, uint32_t views) const;

 private:
  LumiConvShape shape_;
  vk::ComputeKernel kernel_;
};

LumiTensor lumi_conv_reference(const LumiTensor& source, std::span<const float> parameters, size_t weight_offset,
                               const LumiConvShape& shape);

}  // namespace rt::passes
