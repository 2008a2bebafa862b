#include "pipeline/lumi_net.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "shared/lumi_net.h"
#include "vulkan/resources.h"

namespace rt::pipeline {

// Every tensor has its own buffer: the frame graph orders passes by what they read and write,
// so a buffer written twice in a frame would tie the layers in a cycle.
struct LumiNetBlender::Buffers {
  std::vector<passes::LumiConvWeights> weights;  // one per layer
  vk::Buffer inputs, coverage;
  std::vector<vk::Buffer> layer_outputs;  // the last one holds the logits
  std::vector<vk::Buffer> pooled;         // one per layer, empty where no pooling feeds it
  vk::Buffer blending_small, blending_full;
};

namespace {

vk::Buffer tensor_buffer(vk::Context& context, const std::string& name, size_t floats) {
  return vk::Buffer(context, {.name = name, .size = std::max<size_t>(floats, 1) * sizeof(float)});
}

}  // namespace

LumiNetBlender::LumiNetBlender(vk::Context& context, ibr::LumiNetModel model, uint32_t width, uint32_t height,
                               uint32_t max_views)
    : model_(std::move(model)),
      layers_(ibr::lumi_layers(model_.shape)),
      width_(width),
      height_(height),
      max_views_(max_views),
      input_(context),
      softmax_(context),
      upsample_(context),
      blend_(context) {
  if (model_.parameters.size() != ibr::lumi_parameter_count(model_.shape))
    throw std::invalid_argument("Lumi-Net: the parameters do not match the network's shape");
  for (const ibr::LumiLayer& layer : layers_)
    convs_.push_back(std::make_unique<passes::LumiConvPass>(
        context, passes::LumiConvShape{layer.in_channels, layer.out_channels, layer.kernel_size, layer.relu}));
  if (model_.shape.blocks > 0) pool_ = std::make_unique<passes::LumiPoolPass>(context, model_.shape.channels);
  const uint32_t scale = model_.shape.scale;
  const size_t small = size_t(passes::lumi_small_size(width, scale)) * passes::lumi_small_size(height, scale);
  const size_t c = model_.shape.channels, v = max_views;
  buffers_ = std::make_unique<Buffers>(Buffers{
      {},
      tensor_buffer(context, "lumi inputs", small * v * RT_LUMI_INPUT_CHANNELS),
      tensor_buffer(context, "lumi coverage", small * v),
      {},
      {},
      tensor_buffer(context, "lumi blending small", small * (1 + v)),
      tensor_buffer(context, "lumi blending", size_t(width) * height * (1 + v)),
  });
  for (const ibr::LumiLayer& layer : layers_) {
    buffers_->layer_outputs.push_back(tensor_buffer(context, "lumi " + layer.name, small * v * layer.out_channels));
    buffers_->pooled.push_back(layer.pooled_before
                                   ? tensor_buffer(context, "lumi pooled for " + layer.name, small * v * 3 * c)
                                   : tensor_buffer(context, "lumi unused pool " + layer.name, 1));
  }
  for (size_t i = 0; i < layers_.size(); ++i)
    buffers_->weights.push_back(
        convs_[i]->upload_weights(context, model_.parameters, layers_[i].offset, "lumi weights " + layers_[i].name));
}

LumiNetBlender::~LumiNetBlender() = default;

vk::Buffer& LumiNetBlender::inputs() { return buffers_->inputs; }
vk::Buffer& LumiNetBlender::coverage() { return buffers_->coverage; }
vk::Buffer& LumiNetBlender::logits() { return buffers_->layer_outputs.back(); }

void LumiNetBlender::add_to(vk::FrameGraph& graph, vk::Image& fused_depth, vk::Image& warped, vk::Image& features,
                            vk::Image& portrait, vk::Image& portrait_depth, uint32_t view_count) {
  if (fused_depth.width() != width_ || fused_depth.height() != height_ || view_count > max_views_)
    throw std::invalid_argument("Lumi-Net: built for " + std::to_string(width_) + "x" + std::to_string(height_) +
                                " and up to " + std::to_string(max_views_) + " views");
  Buffers& b = *buffers_;
  const uint32_t scale = model_.shape.scale;
  const uint32_t sw = passes::lumi_small_size(width_, scale), sh = passes::lumi_small_size(height_, scale);
  input_.add_to(graph, warped, features, b.inputs, b.coverage, width_, height_, view_count, scale);
  vk::Buffer* source = &b.inputs;
  for (size_t i = 0; i < layers_.size(); ++i) {
    const ibr::LumiLayer& layer = layers_[i];
    if (layer.pooled_before) {
      pool_->add_to(graph, "lumi_pool_" + std::to_string(i), *source, b.coverage, b.pooled[i], sw, sh, view_count);
      source = &b.pooled[i];
    }
    convs_[i]->add_to(graph, layer.name, *source, b.weights[i], b.layer_outputs[i], sw, sh, view_count);
    source = &b.layer_outputs[i];
  }
  softmax_.add_to(graph, logits(), b.coverage, b.blending_small, sw, sh, view_count);
  upsample_.add_to(graph, b.blending_small, b.blending_full, width_, height_, 1 + view_count, scale);
  blend_.add_to(graph, fused_depth, warped, features, b.blending_full, portrait, portrait_depth, view_count);
}

passes::LumiTensor lumi_net_logits_reference(const ibr::LumiNetModel& model, const passes::LumiTensor& inputs,
                                             const passes::LumiTensor& coverage) {
  passes::LumiTensor x = inputs;
  for (const ibr::LumiLayer& layer : ibr::lumi_layers(model.shape)) {
    if (layer.pooled_before) x = passes::lumi_pool_reference(x, coverage);
    x = passes::lumi_conv_reference(
        x, model.parameters, layer.offset,
        passes::LumiConvShape{layer.in_channels, layer.out_channels, layer.kernel_size, layer.relu});
  }
  return x;
}

passes::Portrait lumi_net_reference(const ibr::LumiNetModel& model, const HostImage& fused_depth,
                                    const HostImage& warped, const HostImage& features, uint32_t view_count) {
  const uint32_t w = fused_depth.width, h = fused_depth.height, scale = model.shape.scale;
  const passes::LumiInputs in = passes::lumi_input_reference(warped, features, h, view_count, scale);
  const passes::LumiTensor logits = lumi_net_logits_reference(model, in.inputs, in.coverage);
  const passes::LumiTensor small = passes::lumi_softmax_reference(logits, in.coverage);
  const passes::LumiTensor full = passes::lumi_upsample_reference(small, w, h, scale);
  return passes::lumi_blend_reference(fused_depth, warped, features, full, view_count);
}

}  // namespace rt::pipeline
