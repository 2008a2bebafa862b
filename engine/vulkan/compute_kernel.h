#pragma once
// A compute pipeline built from SPIR-V alone: its descriptor layout (one push-descriptor set),
// push-constant range and workgroup size come from the shader's reflection; its knobs are
// specialization constants set by name at the call site.
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "vulkan/handle.h"
#include "vulkan/shader_reflection.h"

namespace rt::vk {

struct Knob {
  std::string name;  // the specialization constant's name in the shader
  std::variant<float, int32_t, uint32_t, bool> value;
};

class ComputeKernel {
 public:
  ComputeKernel(Context& context, std::string name, std::span<const uint32_t> spirv, const std::vector<Knob>& knobs = {});

  const std::string& name() const { return name_; }
  const ShaderReflection& reflection() const { return reflection_; }
  VkPipeline pipeline() const { return pipeline_.get(); }
  VkPipelineLayout layout() const { return layout_.get(); }

  // Workgroups that cover `threads` invocations per axis (a thread count, never a group count).
  std::array<uint32_t, 3> group_count(std::array<uint32_t, 3> threads) const;

 private:
  std::string name_;
  ShaderReflection reflection_;
  Handle<VkDescriptorSetLayout> set_layout_;
  Handle<VkPipelineLayout> layout_;
  Handle<VkPipeline> pipeline_;
};

}  // namespace rt::vk
