#pragma once
// Pass: Lumi-Net's input tensor from the warped views (shaders/lumi_input.comp), at the network's
// resolution: ceil(width / scale) x ceil(height / scale), each value the mean over the
// scale x scale block's pixels that the view sees (0 where it sees none).
//   in:  warped and features rgba32f atlases (ibr_warp), view_count bands of the target's size
//   out: inputs tensor (views, RT_LUMI_INPUT_CHANNELS, h, w): red, green, blue, coverage (the
//        fraction of the block the view sees), angle penalty (radians), resolution penalty
//        (metres), field-of-view feather; coverage tensor (views, 1, h, w), the same coverage
#include "passes/common/lumi_tensor.h"
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

uint32_t lumi_small_size(uint32_t full, uint32_t scale);  // ceil(full / scale)

class LumiInputPass {
 public:
  explicit LumiInputPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Image& warped, vk::Image& features, vk::Buffer& inputs, vk::Buffer& coverage,
              uint32_t width, uint32_t height, uint32_t view_count, uint32_t scale) const;

 private:
  vk::ComputeKernel kernel_;
};

struct LumiInputs {
  LumiTensor inputs;
  LumiTensor coverage;
};
LumiInputs lumi_input_reference(const HostImage& warped, const HostImage& features, uint32_t height,
                                uint32_t view_count, uint32_t scale);

}  // namespace rt::passes
