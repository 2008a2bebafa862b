#pragma once
// Pass: the fused layer over the background, for the display.
//   in:  fused rgba32f (premultiplied), background rgba32f (rgb used)
//   out: display rgba8, c = C_f + c_bg (1 - alpha_f), alpha 1.
// Non-finite inputs count as 0; a premultiplied color above its alpha is clamped to it.
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class CompositePass {
 public:
  explicit CompositePass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Image& fused, vk::Image& background, vk::Image& display,
              const std::string& pass_name = "composite") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference; its result is RGBA8 (values in [0, 1], quantised to 1/255).
HostImage composite_reference(const HostImage& fused, const HostImage& background);

}  // namespace rt::passes
