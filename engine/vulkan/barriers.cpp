#include "vulkan/barriers.h"

namespace rt::vk {

namespace {
constexpr VkAccessFlags2 kWriteBits =
    VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT |
    VK_ACCESS_2_MEMORY_WRITE_BIT;
}  // namespace

bool writes(VkAccessFlags2 access) { return (access & kWriteBits) != 0; }
bool reads(VkAccessFlags2 access) { return (access & ~kWriteBits) != 0; }

std::optional<BarrierPlan> plan_access(ResourceState& state, const Access& next, bool is_image) {
  const VkImageLayout next_layout = is_image ? next.layout : VK_IMAGE_LAYOUT_UNDEFINED;
  const bool layout_change = is_image && state.layout != next_layout;
  BarrierPlan plan;
  plan.dst_stages = next.stages;
  plan.dst_access = next.access;
  plan.old_layout = state.layout;
  plan.new_layout = next_layout;

  if (writes(next.access) || layout_change) {
    // Write-after-write needs the earlier write made available; write-after-read only needs the
    // reads finished. A layout transition is a write of its own.
    plan.src_stages = state.write_stages | state.read_stages;
    plan.src_access = state.write_access;
    const bool needed = layout_change || plan.src_stages != VK_PIPELINE_STAGE_2_NONE;
    const bool next_writes = writes(next.access);
    state.layout = next_layout;
    // After a read-only transition, later readers in other stages must still wait for it.
    state.write_stages = next.stages;
    state.write_access = next_writes ? next.access : VK_ACCESS_2_NONE;
    state.read_stages = next_writes ? VK_PIPELINE_STAGE_2_NONE : next.stages;
    state.read_access = next_writes ? VK_ACCESS_2_NONE : next.access;
    if (!needed) return std::nullopt;
    return plan;
  }

  // A read in the same layout.
  const bool covered = (state.read_stages & next.stages) == next.stages &&
                       (state.read_access & next.access) == next.access;
  state.read_stages |= next.stages;
  state.read_access |= next.access;
  if (state.write_stages == VK_PIPELINE_STAGE_2_NONE || covered) return std::nullopt;
  plan.src_stages = state.write_stages;
  plan.src_access = state.write_access;
  return plan;
}

}  // namespace rt::vk
