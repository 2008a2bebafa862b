#pragma once
// Lumi-Net's forward pass on the GPU as a chain of passes (passes/lumi_*), and the same network
// as a chain of their C++ references: the warped views in, the portrait out. It blends as
// passes::IbrBlendPass does, from the same inputs, so the image-based model can take either.
#include <memory>
#include <vector>

#include "ibr/lumi_net_model.h"
#include "passes/ibr_blend.h"
#include "passes/lumi_blend.h"
#include "passes/lumi_conv.h"
#include "passes/lumi_input.h"
#include "passes/lumi_pool.h"
#include "passes/lumi_softmax.h"
#include "passes/lumi_upsample.h"

namespace rt::pipeline {

class LumiNetBlender {
 public:
  // Buffers for a width x height target and up to `max_views` views.
  LumiNetBlender(vk::Context& context, ibr::LumiNetModel model, uint32_t width, uint32_t height, uint32_t max_views);
  ~LumiNetBlender();

  void add_to(vk::FrameGraph& graph, vk::Image& fused_depth, vk::Image& warped, vk::Image& features,
              vk::Image& portrait, vk::Image& portrait_depth, uint32_t view_count);

  const ibr::LumiNetModel& model() const { return model_; }
  // At the network's resolution, for the peer check: the input tensors lumi_input wrote and the
  // head's logits (views, 2, h, w).
  vk::Buffer& inputs();
  vk::Buffer& coverage();
  vk::Buffer& logits();

 private:
  struct Buffers;
  ibr::LumiNetModel model_;
  std::vector<ibr::LumiLayer> layers_;
  uint32_t width_, height_, max_views_;
  passes::LumiInputPass input_;
  std::vector<std::unique_ptr<passes::LumiConvPass>> convs_;  // one per layer
  std::unique_ptr<passes::LumiPoolPass> pool_;
  passes::LumiSoftmaxPass softmax_;
  passes::LumiUpsamplePass upsample_;
  passes::LumiBlendPass blend_;
  std::unique_ptr<Buffers> buffers_;
};

// The network from its input tensors to the head's logits (views, 2, h, w).
passes::LumiTensor lumi_net_logits_reference(const ibr::LumiNetModel& model, const passes::LumiTensor& inputs,
                                             const passes::LumiTensor& coverage);
// The whole forward pass, reference by reference.
passes::Portrait lumi_net_reference(const ibr::LumiNetModel& model, const HostImage& fused_depth,
                                    const HostImage& warped, const HostImage& features, uint32_t view_count);

}  // namespace rt::pipeline
