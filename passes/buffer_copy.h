#pragma once
// Pass: a storage-buffer copy kernel (shaders/buffer_copy.comp), one of the bandwidth rooflines
// the benchmarks measure in the same run (pipeline/roofline.h).
//   in:  source, a storage buffer of uvec4 (its size a multiple of 16 bytes)
//   out: destination, the same bytes, bit for bit
#include "vulkan/frame_graph.h"

namespace rt::passes {

class BufferCopyPass {
 public:
  explicit BufferCopyPass(vk::Context& context);
  // Copies the first `bytes` (a multiple of 16, at most either buffer's size).
  void add_to(vk::FrameGraph& graph, vk::Buffer& source, vk::Buffer& destination, uint64_t bytes,
              const std::string& pass_name = "buffer_copy") const;

 private:
  vk::ComputeKernel kernel_;
};

// The invocations one dispatch runs: enough to fill any device, few enough for one dispatch.
uint32_t buffer_copy_invocations(uint64_t elements);

}  // namespace rt::passes
