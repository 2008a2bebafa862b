#pragma once
// Vulkan results turned into exceptions that say which call failed and why.
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace rt::vk {

class VulkanError : public std::runtime_error {
 public:
  VulkanError(const std::string& call, VkResult result);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

const char* result_name(VkResult result);

inline void check(VkResult result, const char* call) {
  if (result != VK_SUCCESS) throw VulkanError(call, result);
}

}  // namespace rt::vk

#define RT_VK_CHECK(call) ::rt::vk::check((call), #call)
