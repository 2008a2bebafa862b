#pragma once
// Pass: distance-based alpha of the geometry hand layer (paper Eq. 4).
//   in:  hand_mask  r32f, coverage of the rasterized hand in [0, 1]
//   out: hand_alpha r32f, alpha_g = coverage * (d_max - clip(d, d_min, d_max)) / (d_max - d_min)
// d (hand distance to the screen, metres) is read every frame; NaN or Inf gives alpha 0.
#include <functional>

#include "image/host_image.h"
#include "shared/config.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct FusionRamp {
  float d_min_m = float(RT_FUSION_D_MIN_M);  // paper: the hand is all mesh from here to the screen
  float d_max_m = float(RT_FUSION_D_MAX_M);  // paper: the hand is all image-based from here on
};

// Throws unless 0 <= d_min < d_max, both finite; returns the ramp.
const FusionRamp& check_ramp(const FusionRamp& ramp);

class HandAlphaPass {
 public:
  explicit HandAlphaPass(vk::Context& context, FusionRamp ramp = {});
  void add_to(vk::FrameGraph& graph, vk::Image& hand_mask, vk::Image& hand_alpha,
              std::function<float()> hand_distance_m, const std::string& pass_name = "hand_alpha") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference.
float hand_alpha_of_distance(float hand_distance_m, const FusionRamp& ramp);
HostImage hand_alpha_reference(const HostImage& hand_mask, float hand_distance_m, const FusionRamp& ramp = {});

}  // namespace rt::passes
