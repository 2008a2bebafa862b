#include "pipeline/receiver_compositor.h"

namespace rt::pipeline {

ReceiverCompositor::ReceiverCompositor(vk::Context& context, uint32_t width, uint32_t height, bool keep_layers)
    : ReceiverCompositor(context, make_demo_layers(width, height), keep_layers) {}

ReceiverCompositor::ReceiverCompositor(vk::Context& context, const HostImage& background_image, bool keep_layers)
    : ReceiverCompositor(context, DemoLayers{HostImage(background_image.width, background_image.height, PixelFormat::RGBA32F),
                                             HostImage(background_image.width, background_image.height, PixelFormat::RGBA32F),
                                             HostImage(background_image.width, background_image.height, PixelFormat::R32F),
                                             background_image},
                         keep_layers) {}

ReceiverCompositor::ReceiverCompositor(vk::Context& context, const DemoLayers& layers, bool keep)
    : portrait(context, {"portrait", layers.portrait.width, layers.portrait.height, PixelFormat::RGBA32F}),
      hand_color(context, {"hand color", layers.portrait.width, layers.portrait.height, PixelFormat::RGBA32F}),
      hand_mask(context, {"hand mask", layers.portrait.width, layers.portrait.height, PixelFormat::R32F}),
      background(context, {"background", layers.portrait.width, layers.portrait.height, PixelFormat::RGBA32F}),
      display(context, {"display", layers.portrait.width, layers.portrait.height, PixelFormat::RGBA8}) {
  const uint32_t width = layers.portrait.width, height = layers.portrait.height;
  if (keep) {
    hand_alpha = std::make_unique<vk::Image>(context, vk::ImageDesc{"hand alpha", width, height, PixelFormat::R32F});
    fused = std::make_unique<vk::Image>(context, vk::ImageDesc{"fused", width, height, PixelFormat::RGBA32F});
    hand_alpha_pass.emplace(context);
    overlay_pass.emplace(context);
    composite_pass.emplace(context);
  } else {
    one_pass.emplace(context);
  }
  vk::upload(context, portrait, layers.portrait);
  vk::upload(context, hand_color, layers.hand_color);
  vk::upload(context, hand_mask, layers.hand_mask);
  vk::upload(context, background, layers.background);
}

void ReceiverCompositor::add_to(vk::FrameGraph& graph, std::function<float()> hand_distance_m) {
  if (one_pass) {
    one_pass->add_to(graph, hand_mask, hand_color, portrait, background, display, std::move(hand_distance_m));
    return;
  }
  hand_alpha_pass->add_to(graph, hand_mask, *hand_alpha, std::move(hand_distance_m));
  overlay_pass->add_to(graph, hand_color, *hand_alpha, portrait, *fused);
  composite_pass->add_to(graph, *fused, background, display);
}

}  // namespace rt::pipeline
