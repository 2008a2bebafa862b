#include "passes/receiver_composite.h"

#include <stdexcept>

#include "passes/composite.h"
#include "passes/overlay.h"

#include "receiver_composite.comp.h"

namespace rt::passes {

ReceiverCompositePass::ReceiverCompositePass(vk::Context& context, FusionRamp ramp)
    : kernel_(context, "receiver_composite", receiver_composite_comp_spirv,
              {{"d_min_m", check_ramp(ramp).d_min_m}, {"d_max_m", ramp.d_max_m}}) {}

void ReceiverCompositePass::add_to(vk::FrameGraph& graph, vk::Image& hand_mask, vk::Image& hand_color,
                                   vk::Image& portrait, vk::Image& background, vk::Image& display,
                                   std::function<float()> hand_distance_m) const {
  for (const vk::Image* image : {&hand_mask, &hand_color, &portrait, &background})
    if (image->width() != display.width() || image->height() != display.height())
      throw std::invalid_argument("receiver_composite: '" + image->name() + "' differs in size from '" + display.name() +
                                  "'");
  graph.add_compute_pass({
      .name = "receiver_composite",
      .kernel = &kernel_,
      .bindings = {{"hand_mask", &hand_mask},
                   {"hand_color", &hand_color},
                   {"portrait", &portrait},
                   {"background", &background},
                   {"display", &display}},
      .threads = {display.width(), display.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::HandAlphaParams>(
          [distance = std::move(hand_distance_m)] { return shader_abi::HandAlphaParams{distance()}; }),
  });
}

HostImage receiver_composite_reference(const HostImage& hand_mask, const HostImage& hand_color, const HostImage& portrait,
                                       const HostImage& background, float hand_distance_m, const FusionRamp& ramp) {
  return composite_reference(overlay_reference(hand_color, hand_alpha_reference(hand_mask, hand_distance_m, ramp), portrait),
                             background);
}

}  // namespace rt::passes
