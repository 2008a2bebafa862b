#include "passes/buffer_copy.h"

#include <algorithm>
#include <stdexcept>

#include "shared/config.h"

#include "buffer_copy.comp.h"

namespace rt::passes {

BufferCopyPass::BufferCopyPass(vk::Context& context) : kernel_(context, "buffer_copy", buffer_copy_comp_spirv) {}

uint32_t buffer_copy_invocations(uint64_t elements) {
  constexpr uint64_t kMaxInvocations = 65535ull * 256;  // one dispatch of the kernel's 256-wide groups
  return uint32_t(std::clamp<uint64_t>(elements, 1, kMaxInvocations));
}

void BufferCopyPass::add_to(vk::FrameGraph& graph, vk::Buffer& source, vk::Buffer& destination, uint64_t bytes,
                            const std::string& pass_name) const {
  if (bytes % 16 != 0) throw std::invalid_argument(pass_name + ": copies whole 16-byte elements, not " + std::to_string(bytes) + " bytes");
  if (bytes > source.size() || bytes > destination.size())
    throw std::invalid_argument(pass_name + ": " + std::to_string(bytes) + " bytes do not fit '" + source.name() + "' and '" +
                                destination.name() + "'");
  if (bytes / 16 > UINT32_MAX) throw std::invalid_argument(pass_name + ": over 2^32 elements");
  const uint32_t count = uint32_t(bytes / 16);
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"Source", &source}, {"Destination", &destination}},
      .threads = {buffer_copy_invocations(count), 1, 1},
      .push_constants = vk::push_constants_from<shader_abi::BufferCopyParams>(
          [count] { return shader_abi::BufferCopyParams{count}; }),
  });
}

}  // namespace rt::passes
