#pragma once
// How a resource is used by one step, what it was last used for, and the barrier between them.
// Pure bookkeeping on Vulkan enums (no Vulkan objects), so the rules are unit-tested directly.
#include <vulkan/vulkan.h>

#include <optional>

namespace rt::vk {

struct Access {
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  // ignored for buffers
};

namespace access {
inline constexpr Access compute_read{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                                     VK_IMAGE_LAYOUT_GENERAL};
inline constexpr Access compute_write{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                                      VK_IMAGE_LAYOUT_GENERAL};
inline constexpr Access compute_read_write{
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_IMAGE_LAYOUT_GENERAL};
inline constexpr Access compute_sample{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                                       VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
// All transfer commands (copies, clears, blits), so that one access fits each of them.
inline constexpr Access transfer_read{VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
inline constexpr Access transfer_write{VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
inline constexpr Access graphics_read{VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_IMAGE_LAYOUT_GENERAL};
inline constexpr Access color_attachment_write{VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                               VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                                               VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
inline constexpr Access depth_attachment_write{
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL};
// A dispatch's workgroup counts, read from a buffer (vkCmdDispatchIndirect).
inline constexpr Access indirect_read{VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT,
                                      VK_IMAGE_LAYOUT_UNDEFINED};
inline constexpr Access host_read{VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED};
}  // namespace access

bool writes(VkAccessFlags2 access);
bool reads(VkAccessFlags2 access);

// What the resource saw since its last barrier-relevant event. Owned by the resource, updated
// by every step that records a use of it (frame graph, upload, readback).
struct ResourceState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 write_stages = VK_PIPELINE_STAGE_2_NONE;  // the last write (or layout transition)
  VkAccessFlags2 write_access = VK_ACCESS_2_NONE;
  VkPipelineStageFlags2 read_stages = VK_PIPELINE_STAGE_2_NONE;  // reads since then that already waited for it
  VkAccessFlags2 read_access = VK_ACCESS_2_NONE;
};

struct BarrierPlan {
  VkPipelineStageFlags2 src_stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 src_access = VK_ACCESS_2_NONE;
  VkPipelineStageFlags2 dst_stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 dst_access = VK_ACCESS_2_NONE;
  VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImageLayout new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

// The barrier needed before `next` (none for a read that an earlier barrier already covers),
// and `state` updated to include `next`. `is_image` decides whether layouts count.
std::optional<BarrierPlan> plan_access(ResourceState& state, const Access& next, bool is_image);

}  // namespace rt::vk
