#pragma once
// Which physical device to run on, decided from plain facts about each one so that the rule
// (prefer a GPU, fall back to a CPU driver such as lavapipe, honour --device) is testable
// without the devices themselves.
#include <vulkan/vulkan.h>

#include <optional>
#include <string>
#include <vector>

namespace rt::vk {

struct DeviceFacts {
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t api_version = 0;
  bool has_compute_queue_with_timestamps = false;
  std::vector<std::string> missing_extensions;
  std::vector<std::string> missing_features;
};

struct DeviceChoice {
  std::optional<size_t> index;  // empty when no device fits
  std::string explanation;      // why each device was rejected, or why this one was taken
};

// The reason a device cannot run the engine, or empty when it can.
std::string rejection_reason(const DeviceFacts& device);

// requested_name: empty for automatic choice, else a case-insensitive substring of the device
// name (e.g. "llvmpipe", "NVIDIA"); requested_by: what the user set it with, named in the
// explanation ("--device", or the environment variable "REMOTETOUCH_DEVICE").
DeviceChoice choose_device(const std::vector<DeviceFacts>& devices, const std::string& requested_name,
                           const std::string& requested_by = "--device");

const char* device_type_name(VkPhysicalDeviceType type);

}  // namespace rt::vk
