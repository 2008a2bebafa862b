#pragma once
// Pass: one workgroup adds the color statistics' partial sums and folds means and standard
// deviations of L, alpha, beta into the running appearance state (paper Eq. 3, smoothed over
// frames: the new frame weighs hand::appearance_weight(updates so far, smoothing), the running mean
// at first, then `smoothing`). Fewer than min_pixels valid pixels, or a non-finite result, leave
// the state unchanged and do not count as an update (header.z still records the pixel count).
//   in:  partials (ColorStatsPartial[group_count])
//   in/out: state (AppearanceState)
// Tested in tests/test_hand_color_reduce.cpp, and in tests/test_hand_color_stats.cpp with the pass
// that feeds it.
#include <span>

#include "shared/config.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::AppearanceState;
using shader_abi::ColorStatsReduceParams;

class HandColorReducePass {
 public:
  explicit HandColorReducePass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Buffer& partials, vk::Buffer& state, std::function<ColorStatsReduceParams()> params,
              const std::string& pass_name = "hand_color_reduce") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference, in double precision.
AppearanceState color_reduce_reference(std::span<const shader_abi::ColorStatsPartial> partials, const AppearanceState& state,
                                       const ColorStatsReduceParams& params);

}  // namespace rt::passes
