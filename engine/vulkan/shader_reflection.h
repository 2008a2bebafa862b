#pragma once
// What a compiled shader declares, read from its SPIR-V (through SPIRV-Cross): bindings with
// their names, types, formats and read/write qualifiers; the push-constant size; the workgroup
// size; the specialization constants by name. Pipelines, dispatch checks and the frame graph's
// reads and writes all come from here, never from hand-kept tables.
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace rt::vk {

struct ShaderBinding {
  std::string name;
  uint32_t set = 0;
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  VkFormat image_format = VK_FORMAT_UNDEFINED;  // storage images: the format the shader declares
  bool readable = true;                         // false for `writeonly`
  bool writable = true;                         // false for `readonly` and for sampled images
  VkShaderStageFlags stages = 0;                // the stages that declare it
};

enum class ScalarType { Float, Int, Uint, Bool };

struct ShaderSpecConstant {
  std::string name;
  uint32_t constant_id = 0;
  ScalarType type = ScalarType::Float;
};

struct ShaderReflection {
  VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;
  std::array<uint32_t, 3> workgroup_size{1, 1, 1};
  uint32_t push_constant_size = 0;
  std::vector<ShaderBinding> bindings;
  std::vector<ShaderSpecConstant> spec_constants;

  const ShaderBinding* find_binding(const std::string& name) const;
  const ShaderSpecConstant* find_spec_constant(const std::string& name) const;
};

// `shader_name` only labels error messages.
ShaderReflection reflect_shader(const std::string& shader_name, std::span<const uint32_t> spirv);

// Throws, naming the shader and each constant, unless every specialization constant `shader`
// declares is among `set_names`. Kernels call it so that a knob's default lives in one place,
// the pass's C++ settings: a constant the C++ side forgot would silently take the shader's
// initial value, a second default that can disagree with the first.
void require_spec_constants_set(const std::string& shader_name, const ShaderReflection& shader,
                                std::span<const std::string> set_names);

}  // namespace rt::vk
