#pragma once
// A compute pipeline built from SPIR-V alone: its descriptor layout (one push-descriptor set),
// push-constant range and workgroup size come from the shader's reflection; its knobs are
// specialization constants set by name at the call site, every one the shader declares (the
// kernel refuses to build otherwise, so that a knob's default lives only in C++).
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vulkan/pipeline_parts.h"

namespace rt::vk {

class ComputeKernel {
 public:
  ComputeKernel(Context& context, std::string name, std::span<const uint32_t> spirv, const std::vector<Knob>& knobs = {});

  const std::string& name() const { return interface_.name; }
  const ShaderReflection& reflection() const { return reflection_; }
  const PipelineInterface& interface() const { return interface_; }
  VkPipeline pipeline() const { return pipeline_.get(); }
  VkPipelineLayout layout() const { return layout_.layout.get(); }

  // Workgroups that cover `threads` invocations per axis (a thread count, never a group count).
  std::array<uint32_t, 3> group_count(std::array<uint32_t, 3> threads) const;

 private:
  ShaderReflection reflection_;
  PipelineInterface interface_;
  PipelineLayoutParts layout_;
  Handle<VkPipeline> pipeline_;
};

}  // namespace rt::vk
