#include "pipeline/receiver_compositor.h"

namespace rt::pipeline {

ReceiverCompositor::ReceiverCompositor(vk::Context& context, uint32_t width, uint32_t height)
    : portrait(context, {"portrait", width, height, PixelFormat::RGBA32F}),
      hand_color(context, {"hand color", width, height, PixelFormat::RGBA32F}),
      hand_mask(context, {"hand mask", width, height, PixelFormat::R32F}),
      background(context, {"background", width, height, PixelFormat::RGBA32F}),
      hand_alpha(context, {"hand alpha", width, height, PixelFormat::R32F}),
      fused(context, {"fused", width, height, PixelFormat::RGBA32F}),
      display(context, {"display", width, height, PixelFormat::RGBA8}),
      hand_alpha_pass(context),
      overlay_pass(context),
      composite_pass(context) {
  const DemoLayers layers = make_demo_layers(width, height);
  vk::upload(context, portrait, layers.portrait);
  vk::upload(context, hand_color, layers.hand_color);
  vk::upload(context, hand_mask, layers.hand_mask);
  vk::upload(context, background, layers.background);
}

ReceiverCompositor::ReceiverCompositor(vk::Context& context, const HostImage& background_image)
    : ReceiverCompositor(context, background_image.width, background_image.height) {
  const HostImage none(background_image.width, background_image.height, PixelFormat::RGBA32F);
  vk::upload(context, portrait, none);
  vk::upload(context, hand_color, none);
  vk::upload(context, hand_mask, HostImage(background_image.width, background_image.height, PixelFormat::R32F));
  vk::upload(context, background, background_image);
}

void ReceiverCompositor::add_to(vk::FrameGraph& graph, std::function<float()> hand_distance_m) {
  hand_alpha_pass.add_to(graph, hand_mask, hand_alpha, std::move(hand_distance_m));
  overlay_pass.add_to(graph, hand_color, hand_alpha, portrait, fused);
  composite_pass.add_to(graph, fused, background, display);
}

}  // namespace rt::pipeline
