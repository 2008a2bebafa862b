#include "vulkan/shader_reflection.h"

#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace rt::vk {
namespace {

struct SpvcContextDeleter {
  void operator()(spvc_context_s* context) const { spvc_context_destroy(context); }
};

VkFormat format_of(SpvImageFormat format) {
  switch (format) {
    case SpvImageFormatR32f: return VK_FORMAT_R32_SFLOAT;
    case SpvImageFormatRgba32f: return VK_FORMAT_R32G32B32A32_SFLOAT;
    case SpvImageFormatRgba8: return VK_FORMAT_R8G8B8A8_UNORM;
    case SpvImageFormatRgba16f: return VK_FORMAT_R16G16B16A16_SFLOAT;
    case SpvImageFormatRg32f: return VK_FORMAT_R32G32_SFLOAT;
    case SpvImageFormatR32ui: return VK_FORMAT_R32_UINT;
    case SpvImageFormatR32i: return VK_FORMAT_R32_SINT;
    case SpvImageFormatR16ui: return VK_FORMAT_R16_UINT;
    case SpvImageFormatR16: return VK_FORMAT_R16_UNORM;
    case SpvImageFormatR8: return VK_FORMAT_R8_UNORM;
    default: return VK_FORMAT_UNDEFINED;
  }
}

VkShaderStageFlagBits stage_of(SpvExecutionModel model) {
  switch (model) {
    case SpvExecutionModelGLCompute: return VK_SHADER_STAGE_COMPUTE_BIT;
    case SpvExecutionModelVertex: return VK_SHADER_STAGE_VERTEX_BIT;
    case SpvExecutionModelFragment: return VK_SHADER_STAGE_FRAGMENT_BIT;
    default: throw std::runtime_error("unsupported shader stage");
  }
}

}  // namespace

const ShaderBinding* ShaderReflection::find_binding(const std::string& name) const {
  for (const auto& binding : bindings)
    if (binding.name == name) return &binding;
  return nullptr;
}

const ShaderSpecConstant* ShaderReflection::find_spec_constant(const std::string& name) const {
  for (const auto& constant : spec_constants)
    if (constant.name == name) return &constant;
  return nullptr;
}

void require_spec_constants_set(const std::string& shader_name, const ShaderReflection& shader,
                                std::span<const std::string> set_names) {
  std::vector<const ShaderSpecConstant*> missing;
  for (const ShaderSpecConstant& constant : shader.spec_constants)
    if (std::find(set_names.begin(), set_names.end(), constant.name) == set_names.end()) missing.push_back(&constant);
  std::sort(missing.begin(), missing.end(), [](auto* a, auto* b) { return a->constant_id < b->constant_id; });
  std::string unset;
  const size_t count = missing.size();
  for (const ShaderSpecConstant* constant : missing)
    unset += std::string(unset.empty() ? "" : ", ") + "'" + constant->name + "' (constant_id " +
             std::to_string(constant->constant_id) + ")";
  if (count == 0) return;
  throw std::invalid_argument("shader '" + shader_name + "': specialization constant" + (count == 1 ? " " : "s ") + unset +
                              (count == 1 ? " is" : " are") +
                              " not set from C++; set every knob from the pass's settings, where its default lives "
                              "(the shader's initial value is only a placeholder)");
}

ShaderReflection reflect_shader(const std::string& shader_name, std::span<const uint32_t> spirv) {
  auto fail = [&](const std::string& what) { return std::runtime_error("reflecting shader '" + shader_name + "': " + what); };
  spvc_context raw_context = nullptr;
  if (spvc_context_create(&raw_context) != SPVC_SUCCESS) throw fail("cannot create a SPIRV-Cross context");
  std::unique_ptr<spvc_context_s, SpvcContextDeleter> context(raw_context);
  spvc_parsed_ir ir = nullptr;
  if (spvc_context_parse_spirv(raw_context, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS)
    throw fail(spvc_context_get_last_error_string(raw_context));
  spvc_compiler compiler = nullptr;
  if (spvc_context_create_compiler(raw_context, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) !=
      SPVC_SUCCESS)
    throw fail(spvc_context_get_last_error_string(raw_context));

  ShaderReflection reflection;
  reflection.stage = stage_of(spvc_compiler_get_execution_model(compiler));
  if (reflection.stage == VK_SHADER_STAGE_COMPUTE_BIT)
    for (unsigned axis = 0; axis < 3; ++axis)
      reflection.workgroup_size[axis] =
          spvc_compiler_get_execution_mode_argument_by_index(compiler, SpvExecutionModeLocalSize, axis);

  spvc_resources resources = nullptr;
  if (spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS)
    throw fail(spvc_context_get_last_error_string(raw_context));

  auto collect = [&](spvc_resource_type resource_type, VkDescriptorType descriptor_type) {
    const spvc_reflected_resource* list = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(resources, resource_type, &list, &count);
    for (size_t i = 0; i < count; ++i) {
      ShaderBinding binding;
      binding.name = list[i].name;
      binding.set = spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationDescriptorSet);
      binding.binding = spvc_compiler_get_decoration(compiler, list[i].id, SpvDecorationBinding);
      binding.type = descriptor_type;
      binding.stages = reflection.stage;
      const spvc_type type = spvc_compiler_get_type_handle(compiler, list[i].type_id);
      if (spvc_type_get_num_array_dimensions(type) != 0)
        throw fail("binding '" + binding.name + "' is an array; the engine binds single resources");
      switch (descriptor_type) {
        case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
          binding.image_format = format_of(spvc_type_get_image_storage_format(type));
          binding.readable = !spvc_compiler_has_decoration(compiler, list[i].id, SpvDecorationNonReadable);
          binding.writable = !spvc_compiler_has_decoration(compiler, list[i].id, SpvDecorationNonWritable);
          break;
        case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
          // glslang puts `readonly`/`writeonly` of a buffer block on its members.
          binding.readable =
              !spvc_compiler_get_member_decoration(compiler, list[i].base_type_id, 0, SpvDecorationNonReadable);
          binding.writable =
              !spvc_compiler_get_member_decoration(compiler, list[i].base_type_id, 0, SpvDecorationNonWritable);
          break;
        default:
          binding.writable = false;
      }
      reflection.bindings.push_back(binding);
    }
  };
  collect(SPVC_RESOURCE_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  collect(SPVC_RESOURCE_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  collect(SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
  collect(SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  for (const auto& binding : reflection.bindings)
    if (binding.set != 0) throw fail("binding '" + binding.name + "' is in set " + std::to_string(binding.set) +
                                     "; passes use set 0 only (one push-descriptor set)");

  const spvc_reflected_resource* push = nullptr;
  size_t push_count = 0;
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_PUSH_CONSTANT, &push, &push_count);
  if (push_count > 0) {
    size_t size = 0;
    spvc_compiler_get_declared_struct_size(compiler, spvc_compiler_get_type_handle(compiler, push[0].base_type_id),
                                           &size);
    reflection.push_constant_size = uint32_t(size);
  }

  const spvc_specialization_constant* constants = nullptr;
  size_t constant_count = 0;
  spvc_compiler_get_specialization_constants(compiler, &constants, &constant_count);
  for (size_t i = 0; i < constant_count; ++i) {
    ShaderSpecConstant constant;
    constant.name = spvc_compiler_get_name(compiler, constants[i].id);
    constant.constant_id = constants[i].constant_id;
    const spvc_constant handle = spvc_compiler_get_constant_handle(compiler, constants[i].id);
    switch (spvc_type_get_basetype(spvc_compiler_get_type_handle(compiler, spvc_constant_get_type(handle)))) {
      case SPVC_BASETYPE_FP32: constant.type = ScalarType::Float; break;
      case SPVC_BASETYPE_INT32: constant.type = ScalarType::Int; break;
      case SPVC_BASETYPE_UINT32: constant.type = ScalarType::Uint; break;
      case SPVC_BASETYPE_BOOLEAN: constant.type = ScalarType::Bool; break;
      default: throw fail("specialization constant '" + constant.name + "' has a type the engine does not set");
    }
    reflection.spec_constants.push_back(constant);
  }
  return reflection;
}

}  // namespace rt::vk
