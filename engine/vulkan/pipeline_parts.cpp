#include "vulkan/pipeline_parts.h"

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

const ShaderBinding* PipelineInterface::find_binding(const std::string& binding_name) const {
  for (const auto& binding : bindings)
    if (binding.name == binding_name) return &binding;
  return nullptr;
}

PipelineInterface merge_interfaces(const std::string& name, std::span<const ShaderReflection> stages) {
  PipelineInterface interface;
  interface.name = name;
  for (const ShaderReflection& stage : stages) {
    for (const ShaderBinding& binding : stage.bindings) {
      ShaderBinding* same_slot = nullptr;
      for (auto& existing : interface.bindings)
        if (existing.binding == binding.binding) same_slot = &existing;
      if (!same_slot) {
        interface.bindings.push_back(binding);
        continue;
      }
      if (same_slot->type != binding.type || same_slot->name != binding.name)
        throw std::invalid_argument("pipeline '" + name + "': binding " + std::to_string(binding.binding) +
                                    " is '" + same_slot->name + "' in one stage and '" + binding.name +
                                    "' (or another type) in another");
      same_slot->stages |= binding.stages;
      same_slot->readable |= binding.readable;
      same_slot->writable |= binding.writable;
    }
    if (stage.push_constant_size > 0) {
      interface.push_constant_size = std::max(interface.push_constant_size, stage.push_constant_size);
      interface.push_constant_stages |= stage.stage;
    }
  }
  return interface;
}

PipelineLayoutParts make_pipeline_layout(Context& context, const PipelineInterface& interface) {
  const uint32_t max_push = context.properties().limits.maxPushConstantsSize;
  if (interface.push_constant_size > max_push)
    throw std::invalid_argument("pipeline '" + interface.name + "' declares " +
                                std::to_string(interface.push_constant_size) +
                                " bytes of push constants; the device allows " + std::to_string(max_push));
  PipelineLayoutParts parts;
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (const auto& binding : interface.bindings)
    bindings.push_back({binding.binding, binding.type, 1, binding.stages, nullptr});
  auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  set_info.bindingCount = uint32_t(bindings.size());
  set_info.pBindings = bindings.data();
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateDescriptorSetLayout(context.device(), &set_info, nullptr, &set_layout));
  parts.set_layout = Handle<VkDescriptorSetLayout>(context, set_layout);
  context.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, uint64_t(set_layout), interface.name + " set layout");

  const VkPushConstantRange push_range{interface.push_constant_stages, 0, interface.push_constant_size};
  auto layout_info = vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set_layout;
  layout_info.pushConstantRangeCount = interface.push_constant_size > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = &push_range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreatePipelineLayout(context.device(), &layout_info, nullptr, &layout));
  parts.layout = Handle<VkPipelineLayout>(context, layout);
  context.set_name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, uint64_t(layout), interface.name + " layout");
  return parts;
}

Specialization make_specialization(const std::string& name, std::span<const ShaderReflection> stages,
                                   const std::vector<Knob>& knobs) {
  Specialization specialization;
  for (const Knob& knob : knobs) {
    const ShaderSpecConstant* constant = nullptr;
    for (const auto& stage : stages)
      if (!constant) constant = stage.find_spec_constant(knob.name);
    if (!constant) {
      std::string known;
      for (const auto& stage : stages)
        for (const auto& c : stage.spec_constants) known += (known.empty() ? "" : ", ") + c.name;
      throw std::invalid_argument("shader '" + name + "' has no knob '" + knob.name + "' (it has: " +
                                  (known.empty() ? "none" : known) + ")");
    }
    if (constant->type != type_of(knob))
      throw std::invalid_argument("knob '" + knob.name + "' of shader '" + name + "' is a " + type_name(constant->type) +
                                  ", given a " + type_name(type_of(knob)));
    specialization.entries.push_back(
        {constant->constant_id, uint32_t(specialization.values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
    specialization.values.push_back(bits_of(knob));
  }
  specialization.info = {uint32_t(specialization.entries.size()), specialization.entries.data(),
                         specialization.values.size() * sizeof(uint32_t), specialization.values.data()};
  return specialization;
}

Handle<VkShaderModule> make_shader_module(Context& context, const std::string& name, std::span<const uint32_t> spirv) {
  auto info = vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  info.codeSize = spirv.size_bytes();
  info.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateShaderModule(context.device(), &info, nullptr, &module));
  context.set_name(VK_OBJECT_TYPE_SHADER_MODULE, uint64_t(module), name);
  return Handle<VkShaderModule>(context, module);
}

}  // namespace rt::vk
