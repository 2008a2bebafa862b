#pragma once
// Pass: the receiver's frame in one (shaders/receiver_composite.comp): Eq. 4, Eq. 5 and the
// composite over the background, with no layer written in between. Its result is that of
// hand_alpha, overlay and composite one after the other (passes/hand_alpha.h, overlay.h,
// composite.h), which a site runs instead when its layers are to be seen (a window's views,
// eval dual's measures).
//   in:  hand_mask r32f (coverage), hand_color rgba32f (straight), portrait rgba32f (straight),
//        background rgba32f (rgb used); the hand's distance to the screen, read every frame
//   out: display rgba8
#include <functional>
#include <string>

#include "image/host_image.h"
#include "passes/hand_alpha.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class ReceiverCompositePass {
 public:
  explicit ReceiverCompositePass(vk::Context& context, FusionRamp ramp = {});
  void add_to(vk::FrameGraph& graph, vk::Image& hand_mask, vk::Image& hand_color, vk::Image& portrait,
              vk::Image& background, vk::Image& display, std::function<float()> hand_distance_m) const;

 private:
  vk::ComputeKernel kernel_;
};

// composite_reference of overlay_reference of hand_alpha_reference: the three references, composed.
HostImage receiver_composite_reference(const HostImage& hand_mask, const HostImage& hand_color, const HostImage& portrait,
                                       const HostImage& background, float hand_distance_m, const FusionRamp& ramp = {});

}  // namespace rt::passes
