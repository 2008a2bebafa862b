#include "vulkan/compute_kernel.h"

#include <cstring>
#include <stdexcept>

#include "vulkan/check.h"
#include "vulkan/vk_struct.h"

namespace rt::vk {
namespace {

const char* type_name(ScalarType type) {
  switch (type) {
    case ScalarType::Float: return "float";
    case ScalarType::Int: return "int";
    case ScalarType::Uint: return "uint";
    case ScalarType::Bool: return "bool";
  }
  return "?";
}

ScalarType type_of(const Knob& knob) {
  switch (knob.value.index()) {
    case 0: return ScalarType::Float;
    case 1: return ScalarType::Int;
    case 2: return ScalarType::Uint;
    default: return ScalarType::Bool;
  }
}

uint32_t bits_of(const Knob& knob) {
  uint32_t bits = 0;
  std::visit(
      [&](auto value) {
        if constexpr (std::is_same_v<decltype(value), bool>) bits = value ? VK_TRUE : VK_FALSE;
        else std::memcpy(&bits, &value, sizeof(bits));
      },
      knob.value);
  return bits;
}

}  // namespace

ComputeKernel::ComputeKernel(Context& context, std::string name, std::span<const uint32_t> spirv,
                             const std::vector<Knob>& knobs)
    : name_(std::move(name)), reflection_(reflect_shader(name_, spirv)) {
  if (reflection_.stage != VK_SHADER_STAGE_COMPUTE_BIT)
    throw std::invalid_argument("shader '" + name_ + "' is not a compute shader");
  const uint32_t max_push = context.properties().limits.maxPushConstantsSize;
  if (reflection_.push_constant_size > max_push)
    throw std::invalid_argument("shader '" + name_ + "' declares " + std::to_string(reflection_.push_constant_size) +
                                " bytes of push constants; the device allows " + std::to_string(max_push));

  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (const auto& binding : reflection_.bindings)
    bindings.push_back({binding.binding, binding.type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
  auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  set_info.bindingCount = uint32_t(bindings.size());
  set_info.pBindings = bindings.data();
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateDescriptorSetLayout(context.device(), &set_info, nullptr, &set_layout));
  set_layout_ = Handle<VkDescriptorSetLayout>(context, set_layout);
  context.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, uint64_t(set_layout), name_ + " set layout");

  const VkPushConstantRange push_range{VK_SHADER_STAGE_COMPUTE_BIT, 0, reflection_.push_constant_size};
  auto layout_info = vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set_layout;
  layout_info.pushConstantRangeCount = reflection_.push_constant_size > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = &push_range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreatePipelineLayout(context.device(), &layout_info, nullptr, &layout));
  layout_ = Handle<VkPipelineLayout>(context, layout);
  context.set_name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, uint64_t(layout), name_ + " layout");

  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  for (const Knob& knob : knobs) {
    const ShaderSpecConstant* constant = reflection_.find_spec_constant(knob.name);
    if (!constant) {
      std::string known;
      for (const auto& c : reflection_.spec_constants) known += (known.empty() ? "" : ", ") + c.name;
      throw std::invalid_argument("shader '" + name_ + "' has no knob '" + knob.name + "' (it has: " +
                                  (known.empty() ? "none" : known) + ")");
    }
    if (constant->type != type_of(knob))
      throw std::invalid_argument("knob '" + knob.name + "' of shader '" + name_ + "' is a " +
                                  type_name(constant->type) + ", given a " + type_name(type_of(knob)));
    entries.push_back({constant->constant_id, uint32_t(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
    values.push_back(bits_of(knob));
  }
  VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(), values.size() * sizeof(uint32_t),
                                      values.data()};

  auto module_info = vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  module_info.codeSize = spirv.size_bytes();
  module_info.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateShaderModule(context.device(), &module_info, nullptr, &module));
  Handle<VkShaderModule> module_handle(context, module);
  context.set_name(VK_OBJECT_TYPE_SHADER_MODULE, uint64_t(module), name_);

  auto pipeline_info = vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  pipeline_info.stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline_info.stage.module = module;
  pipeline_info.stage.pName = "main";
  pipeline_info.stage.pSpecializationInfo = entries.empty() ? nullptr : &specialization;
  pipeline_info.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateComputePipelines(context.device(), context.pipeline_cache(), 1, &pipeline_info, nullptr, &pipeline));
  pipeline_ = Handle<VkPipeline>(context, pipeline);
  context.set_name(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), name_);
}

std::array<uint32_t, 3> ComputeKernel::group_count(std::array<uint32_t, 3> threads) const {
  std::array<uint32_t, 3> groups{};
  for (int axis = 0; axis < 3; ++axis) {
    const uint32_t size = reflection_.workgroup_size[axis];
    groups[axis] = (threads[axis] + size - 1) / size;
  }
  return groups;
}

}  // namespace rt::vk
