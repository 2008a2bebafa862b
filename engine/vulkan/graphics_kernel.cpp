#include "vulkan/graphics_kernel.h"

#include <array>
#include <stdexcept>

#include "vulkan/check.h"
#include "vulkan/resources.h"
#include "vulkan/vk_struct.h"

namespace rt::vk {

GraphicsKernel::GraphicsKernel(Context& context, std::string name, std::span<const uint32_t> vertex_spirv,
                               std::span<const uint32_t> fragment_spirv, const GraphicsTargets& targets,
                               const std::vector<Knob>& knobs)
    : targets_(targets) {
  const std::array<ShaderReflection, 2> stages = {reflect_shader(name + " (vertex)", vertex_spirv),
                                                  reflect_shader(name + " (fragment)", fragment_spirv)};
  if (stages[0].stage != VK_SHADER_STAGE_VERTEX_BIT || stages[1].stage != VK_SHADER_STAGE_FRAGMENT_BIT)
    throw std::invalid_argument("graphics kernel '" + name + "' needs a vertex and a fragment shader, in that order");
  for (PixelFormat format : targets.color)
    if (format == PixelFormat::D32F) throw std::invalid_argument("graphics kernel '" + name + "': d32f is not a color format");
  interface_ = merge_interfaces(name, stages);
  interface_.bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;
  layout_ = make_pipeline_layout(context, interface_);
  Specialization specialization = make_specialization(name, stages, knobs);
  std::vector<std::string> knob_names;
  for (const Knob& knob : knobs) knob_names.push_back(knob.name);
  require_spec_constants_set(name + " (vertex)", stages[0], knob_names);
  require_spec_constants_set(name + " (fragment)", stages[1], knob_names);
  const Handle<VkShaderModule> vertex = make_shader_module(context, name + " (vertex)", vertex_spirv);
  const Handle<VkShaderModule> fragment = make_shader_module(context, name + " (fragment)", fragment_spirv);

  std::array<VkPipelineShaderStageCreateInfo, 2> shader_stages{};
  for (int i = 0; i < 2; ++i) {
    shader_stages[i] = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    shader_stages[i].stage = stages[i].stage;
    shader_stages[i].module = i == 0 ? vertex.get() : fragment.get();
    shader_stages[i].pName = "main";
    shader_stages[i].pSpecializationInfo = specialization.get();
  }
  auto vertex_input = vk_struct<VkPipelineVertexInputStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
  auto assembly = vk_struct<VkPipelineInputAssemblyStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  auto viewport = vk_struct<VkPipelineViewportStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  auto raster = vk_struct<VkPipelineRasterizationStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = VK_CULL_MODE_NONE;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  auto multisample = vk_struct<VkPipelineMultisampleStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  auto depth = vk_struct<VkPipelineDepthStencilStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  depth.depthTestEnable = targets.depth ? VK_TRUE : VK_FALSE;
  depth.depthWriteEnable = targets.depth ? VK_TRUE : VK_FALSE;
  depth.depthCompareOp = VK_COMPARE_OP_LESS;
  std::vector<VkPipelineColorBlendAttachmentState> blend(targets.color.size());
  for (auto& attachment : blend) {
    attachment.blendEnable = VK_FALSE;
    attachment.colorWriteMask =
        VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  }
  auto color_blend = vk_struct<VkPipelineColorBlendStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  color_blend.attachmentCount = uint32_t(blend.size());
  color_blend.pAttachments = blend.data();
  const std::array<VkDynamicState, 2> dynamic_states = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  auto dynamic = vk_struct<VkPipelineDynamicStateCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = uint32_t(dynamic_states.size());
  dynamic.pDynamicStates = dynamic_states.data();

  std::vector<VkFormat> color_formats;
  for (PixelFormat format : targets.color) color_formats.push_back(vulkan_format(format));
  auto rendering = vk_struct<VkPipelineRenderingCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO);
  rendering.colorAttachmentCount = uint32_t(color_formats.size());
  rendering.pColorAttachmentFormats = color_formats.data();
  rendering.depthAttachmentFormat = targets.depth ? VK_FORMAT_D32_SFLOAT : VK_FORMAT_UNDEFINED;

  auto info = vk_struct<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering);
  info.stageCount = uint32_t(shader_stages.size());
  info.pStages = shader_stages.data();
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &color_blend;
  info.pDynamicState = &dynamic;
  info.layout = layout_.layout.get();
  VkPipeline pipeline = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateGraphicsPipelines(context.device(), context.pipeline_cache(), 1, &info, nullptr, &pipeline));
  pipeline_ = Handle<VkPipeline>(context, pipeline);
  context.set_name(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), name);
  interface_.pipeline = pipeline;
  interface_.layout = layout_.layout.get();
}

}  // namespace rt::vk
