#pragma once
// Pass: a plain rgba32f image copy in a compute shader, the bandwidth roofline that the
// benchmarks set every other pass against (same device, same run).
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

class CopyPass {
 public:
  explicit CopyPass(vk::Context& context);
  void add_to(vk::FrameGraph& graph, vk::Image& source, vk::Image& destination,
              const std::string& pass_name = "copy") const;

 private:
  vk::ComputeKernel kernel_;
};

}  // namespace rt::passes
