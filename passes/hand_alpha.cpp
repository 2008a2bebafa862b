#include "passes/hand_alpha.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "passes/common/reference_math.h"

#include "hand_alpha.comp.h"

namespace rt::passes {

const FusionRamp& check_ramp(const FusionRamp& ramp) {
  if (!std::isfinite(ramp.d_min_m) || !std::isfinite(ramp.d_max_m) || ramp.d_min_m < 0.0f ||
      ramp.d_max_m <= ramp.d_min_m)
    throw std::invalid_argument("fusion ramp needs 0 <= d_min < d_max (metres), got d_min = " +
                                std::to_string(ramp.d_min_m) + ", d_max = " + std::to_string(ramp.d_max_m));
  return ramp;
}

HandAlphaPass::HandAlphaPass(vk::Context& context, FusionRamp ramp)
    : kernel_(context, "hand_alpha", hand_alpha_comp_spirv,
              {{"d_min_m", check_ramp(ramp).d_min_m}, {"d_max_m", ramp.d_max_m}}) {}

void HandAlphaPass::add_to(vk::FrameGraph& graph, vk::Image& hand_mask, vk::Image& hand_alpha,
                           std::function<float()> hand_distance_m, const std::string& pass_name) const {
  if (hand_mask.width() != hand_alpha.width() || hand_mask.height() != hand_alpha.height())
    throw std::invalid_argument(pass_name + ": hand mask and hand alpha differ in size");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"hand_mask", &hand_mask}, {"hand_alpha", &hand_alpha}},
      .threads = {hand_alpha.width(), hand_alpha.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::HandAlphaParams>(
          [distance = std::move(hand_distance_m)] { return shader_abi::HandAlphaParams{distance()}; }),
  });
}

float hand_alpha_of_distance(float d, const FusionRamp& ramp) {
  if (!std::isfinite(d)) return 0.0f;  // no geometry hand
  const float clipped = std::min(std::max(d, ramp.d_min_m), ramp.d_max_m);
  return (ramp.d_max_m - clipped) / (ramp.d_max_m - ramp.d_min_m);
}

HostImage hand_alpha_reference(const HostImage& hand_mask, float hand_distance_m, const FusionRamp& ramp) {
  HostImage alpha(hand_mask.width, hand_mask.height, PixelFormat::R32F);
  const float ramp_alpha = hand_alpha_of_distance(hand_distance_m, ramp);
  for (uint32_t y = 0; y < hand_mask.height; ++y)
    for (uint32_t x = 0; x < hand_mask.width; ++x) {
      alpha.at(x, y) = ramp_alpha * unit_or_zero(hand_mask.at(x, y));
    }
  return alpha;
}

}  // namespace rt::passes
