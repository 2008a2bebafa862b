#include "vulkan/compute_kernel.h"

#include <stdexcept>

#include "vulkan/check.h"
#include "vulkan/vk_struct.h"

namespace rt::vk {
namespace {

std::vector<std::string> knob_names(const std::vector<Knob>& knobs) {
  std::vector<std::string> names;
  for (const Knob& knob : knobs) names.push_back(knob.name);
  return names;
}

}  // namespace

ComputeKernel::ComputeKernel(Context& context, std::string name, std::span<const uint32_t> spirv,
                             const std::vector<Knob>& knobs)
    : reflection_(reflect_shader(name, spirv)) {
  if (reflection_.stage != VK_SHADER_STAGE_COMPUTE_BIT)
    throw std::invalid_argument("shader '" + name + "' is not a compute shader");
  const std::span<const ShaderReflection> stages(&reflection_, 1);
  interface_ = merge_interfaces(name, stages);
  interface_.bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  layout_ = make_pipeline_layout(context, interface_);
  Specialization specialization = make_specialization(name, stages, knobs);
  require_spec_constants_set(name, reflection_, knob_names(knobs));
  const Handle<VkShaderModule> module = make_shader_module(context, name, spirv);

  auto info = vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module.get();
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = specialization.get();
  info.layout = layout_.layout.get();
  VkPipeline pipeline = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateComputePipelines(context.device(), context.pipeline_cache(), 1, &info, nullptr, &pipeline));
  pipeline_ = Handle<VkPipeline>(context, pipeline);
  context.set_name(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), name);
  interface_.pipeline = pipeline;
  interface_.layout = layout_.layout.get();
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
