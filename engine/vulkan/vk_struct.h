#pragma once
// A zero-initialised Vulkan struct with its sType (and pNext) set: the C API's idiom, without
// aggregate initialisers that leave members unnamed.
#include <vulkan/vulkan.h>

namespace rt::vk {

template <typename T>
T vk_struct(VkStructureType type, void* next = nullptr) {
  T value{};
  value.sType = type;
  value.pNext = next;
  return value;
}

}  // namespace rt::vk
