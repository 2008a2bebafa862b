#pragma once
// The receiver's compositing, one chain for the site's display, `compose` and the benchmark:
// hand_alpha (Eq. 4) -> overlay (Eq. 5) -> composite over the background -> display.
#include <functional>

#include "pipeline/demo_layers.h"
#include "passes/composite.h"
#include "passes/hand_alpha.h"
#include "passes/overlay.h"
#include "vulkan/frame_graph.h"

namespace rt::pipeline {

struct ReceiverCompositor {
  // Creates the images at this size and uploads the generated layers into them (compose, bench).
  ReceiverCompositor(vk::Context& context, uint32_t width, uint32_t height);
  // For a site: no portrait and no hand yet, over `background` (rgba32f at this size).
  ReceiverCompositor(vk::Context& context, const HostImage& background);
  // Adds the three passes; hand_distance_m is read when each frame is recorded.
  void add_to(vk::FrameGraph& graph, std::function<float()> hand_distance_m);

  vk::Image portrait, hand_color, hand_mask, background;  // inputs
  vk::Image hand_alpha, fused, display;                   // outputs of the passes
  passes::HandAlphaPass hand_alpha_pass;
  passes::OverlayPass overlay_pass;
  passes::CompositePass composite_pass;

 private:
  // The images at the layers' size, holding them.
  ReceiverCompositor(vk::Context& context, const DemoLayers& layers);
};

}  // namespace rt::pipeline
