#pragma once
// Pass: one convolution layer of Lumi-Net with its bias and optional ReLU fused
// (shaders/lumi_conv.comp): 3x3 or 1x1, zero padding, the same weights for every view.
//   in:  source tensor (views, in_channels, height, width), the layer's weights (LumiConvWeights:
//        uniform buffers made by upload_weights from PyTorch's order (out, in, ky, kx), then the bias)
//   out: result tensor (views, out_channels, height, width)
// Channel counts and the kernel size are specialization constants. One dispatch per group of
// RT_LUMI_CONV_GROUP output channels and chunk of RT_LUMI_CONV_CHANNEL_CHUNK input channels, each
// chunk's weights in a uniform buffer of its own; each chunk after the first adds to the sum the
// one before stored (a kernel for the first chunk, one for those in between, one for the last).
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

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

// A layer's weights on the device: one uniform buffer per group of output channels and chunk of
// input channels, the chunks of group 0 first.
struct LumiConvWeights {
  std::vector<vk::Buffer> chunks;
};

class LumiConvPass {
 public:
  LumiConvPass(vk::Context& context, const LumiConvShape& shape);
  const LumiConvShape& shape() const { return shape_; }
  // The layer's parameters from `weight_offset` of `parameters` (PyTorch's order), on the device.
  LumiConvWeights upload_weights(vk::Context& context, std::span<const float> parameters, size_t weight_offset,
                                 const std::string& name) const;
  // `name` names the pass in the graph (a network has several layers); a layer of more than one
  // group or chunk adds a pass for each, the later ones named after their first output and input
  // channels.
  void add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, LumiConvWeights& weights,
              vk::Buffer& result, uint32_t width, uint32_t height, uint32_t views) const;

 private:
  const vk::ComputeKernel& chunk_kernel(uint32_t chunk) const;

  LumiConvShape shape_;
  // The first chunk's kernel, then those of the chunks in between and of the last, where the
  // layer has them.
  std::vector<std::unique_ptr<vk::ComputeKernel>> kernels_;
};

uint32_t lumi_conv_groups(const LumiConvShape& shape);
uint32_t lumi_conv_chunks(const LumiConvShape& shape);
// What the uniform buffer of group `group` and chunk `chunk` holds (shaders/lumi_conv.comp): the
// group's bias, then for each input channel of the chunk, kernel row and column the group's
// weights, RT_LUMI_CONV_GROUP floats each, zeros past the last output channel.
std::vector<float> lumi_conv_chunk_parameters(std::span<const float> parameters, size_t weight_offset,
                                              const LumiConvShape& shape, uint32_t group, uint32_t chunk);

LumiTensor lumi_conv_reference(const LumiTensor& source, std::span<const float> parameters, size_t weight_offset,
                               const LumiConvShape& shape);

}  // namespace rt::passes
