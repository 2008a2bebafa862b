#pragma once
// Pass: one of the window's debug views (shaders/display_view.comp).
//   in:  source, any image of the pipeline (sampled, read texel by texel), and the band of its
//        rows to show (an atlas holds one band per view)
//   out: view rgba8 at the window's size: the band fitted with its aspect kept, black bars
//        around it; color as it is, depth in metres to white (near) .. black (far) with dark blue
//        where there is none, or one channel to black .. white; magenta where a value is not finite.
#include <string>

#include "image/host_image.h"
#include "vulkan/frame_graph.h"

#include "shared/config.h"

namespace rt::passes {

struct DisplayViewMapping {
  uint32_t mode = RT_VIEW_COLOR;
  uint32_t channel = 0;  // for RT_VIEW_DEPTH and RT_VIEW_CHANNEL
  float low = 0.0f, high = 1.0f;
  uint32_t band_y0 = 0, band_height = 0;  // band_height 0: the whole source
};

class DisplayViewPass {
 public:
  explicit DisplayViewPass(vk::Context& context);
  // `mapping` is read when each frame is recorded, so a view can change band or range freely.
  void add_to(vk::FrameGraph& graph, vk::Image& source, vk::Image& view, std::function<DisplayViewMapping()> mapping,
              const std::string& pass_name = "display_view") const;

 private:
  vk::ComputeKernel kernel_;
  vk::Sampler sampler_;
};

// The plain C++ reference: rgba8 at width x height (values quantised to 1/255).
HostImage display_view_reference(const HostImage& source, const DisplayViewMapping& mapping, uint32_t width,
                                 uint32_t height);

}  // namespace rt::passes
