#include "vulkan/handle.h"

namespace rt::vk {

template <>
void destroy_object(const Context& c, VkBuffer o) { vkDestroyBuffer(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkImage o) { vkDestroyImage(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkImageView o) { vkDestroyImageView(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkDeviceMemory o) { vkFreeMemory(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkSampler o) { vkDestroySampler(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkPipeline o) { vkDestroyPipeline(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkPipelineLayout o) { vkDestroyPipelineLayout(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkDescriptorSetLayout o) { vkDestroyDescriptorSetLayout(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkShaderModule o) { vkDestroyShaderModule(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkQueryPool o) { vkDestroyQueryPool(c.device(), o, nullptr); }
template <>
void destroy_object(const Context& c, VkCommandBuffer o) {
  const auto pool = c.lock_command_pool();
  vkFreeCommandBuffers(c.device(), c.command_pool(), 1, &o);
}

}  // namespace rt::vk
