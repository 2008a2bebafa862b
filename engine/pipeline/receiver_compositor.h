#pragma once
// The receiver's compositing, one chain for the site's display, `compose` and the benchmark:
// Eq. 4, Eq. 5 and the composite over the background in one pass (receiver_composite), or,
// with the layers kept for inspection, hand_alpha (Eq. 4) -> overlay (Eq. 5) -> composite, each
// writing its layer (the same display).
#include <functional>
#include <memory>
#include <optional>

#include "pipeline/demo_layers.h"
#include "passes/composite.h"
#include "passes/hand_alpha.h"
#include "passes/overlay.h"
#include "passes/receiver_composite.h"
#include "vulkan/frame_graph.h"

namespace rt::pipeline {

struct ReceiverCompositor {
  // Creates the images at this size and uploads the generated layers into them (compose, bench).
  // `keep_layers`: hand_alpha and fused exist and hold each frame's layers (else they are null).
  ReceiverCompositor(vk::Context& context, uint32_t width, uint32_t height, bool keep_layers = false);
  // For a site: no portrait and no hand yet, over `background` (rgba32f at this size).
  ReceiverCompositor(vk::Context& context, const HostImage& background, bool keep_layers = false);
  // Adds the passes; hand_distance_m is read when each frame is recorded.
  void add_to(vk::FrameGraph& graph, std::function<float()> hand_distance_m);

  vk::Image portrait, hand_color, hand_mask, background;  // inputs
  vk::Image display;                                       // the output
  std::unique_ptr<vk::Image> hand_alpha, fused;            // the layers, when kept
  // The three passes when the layers are kept, else the one.
  std::optional<passes::HandAlphaPass> hand_alpha_pass;
  std::optional<passes::OverlayPass> overlay_pass;
  std::optional<passes::CompositePass> composite_pass;
  std::optional<passes::ReceiverCompositePass> one_pass;

 private:
  // The images at the layers' size, holding them.
  ReceiverCompositor(vk::Context& context, const DemoLayers& layers, bool keep_layers);
};

}  // namespace rt::pipeline
