#pragma once
// What compute and graphics pipelines share: the descriptor layout (one push-descriptor set)
// and push-constant range from the shaders' reflection, and specialization constants set by
// name. The frame graph binds any pipeline through PipelineInterface.
#include <vulkan/vulkan.h>

#include <span>
#include <string>
#include <variant>
#include <vector>

#include "vulkan/handle.h"
#include "vulkan/shader_reflection.h"

namespace rt::vk {

struct Knob {
  std::string name;  // the specialization constant's name in the shader(s)
  std::variant<float, int32_t, uint32_t, bool> value;
};

// The part of a pipeline the frame graph needs to bind resources and push constants.
struct PipelineInterface {
  std::string name;
  VkPipelineBindPoint bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::vector<ShaderBinding> bindings;  // merged over the stages
  uint32_t push_constant_size = 0;
  VkShaderStageFlags push_constant_stages = 0;

  const ShaderBinding* find_binding(const std::string& binding_name) const;
};

// Merges the stages' bindings (same slot: same type and name required) and push constants.
PipelineInterface merge_interfaces(const std::string& name, std::span<const ShaderReflection> stages);

struct PipelineLayoutParts {
  Handle<VkDescriptorSetLayout> set_layout;
  Handle<VkPipelineLayout> layout;
};
PipelineLayoutParts make_pipeline_layout(Context& context, const PipelineInterface& interface);

// Specialization data for `knobs`; each knob must name a constant of at least one stage, with
// the same type. The result points into itself: keep it alive until the pipeline is created.
struct Specialization {
  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  VkSpecializationInfo info{};
  const VkSpecializationInfo* get() { return entries.empty() ? nullptr : &info; }
};
Specialization make_specialization(const std::string& name, std::span<const ShaderReflection> stages,
                                   const std::vector<Knob>& knobs);

Handle<VkShaderModule> make_shader_module(Context& context, const std::string& name, std::span<const uint32_t> spirv);

}  // namespace rt::vk
