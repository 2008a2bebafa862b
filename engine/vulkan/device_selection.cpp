#include "vulkan/device_selection.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace rt::vk {
namespace {

// 1.2 with VK_KHR_synchronization2 is enough: RenderDoc 1.24 reports 1.2 for every device.
constexpr uint32_t kRequiredApi = VK_API_VERSION_1_2;

int preference(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

}  // namespace

const char* device_type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

std::string rejection_reason(const DeviceFacts& device) {
  std::vector<std::string> reasons;
  if (device.api_version < kRequiredApi) {
    std::ostringstream text;
    text << "supports Vulkan " << VK_API_VERSION_MAJOR(device.api_version) << "." << VK_API_VERSION_MINOR(device.api_version)
         << ", needs 1.2";
    reasons.push_back(text.str());
  }
  if (!device.has_compute_queue_with_timestamps) reasons.push_back("no graphics+compute queue with timestamps");
  if (!device.missing_extensions.empty()) reasons.push_back("lacks extensions " + join(device.missing_extensions));
  if (!device.missing_features.empty()) reasons.push_back("lacks features " + join(device.missing_features));
  return join(reasons);
}

DeviceChoice choose_device(const std::vector<DeviceFacts>& devices, const std::string& requested_name,
                           const std::string& requested_by) {
  DeviceChoice choice;
  std::ostringstream why;
  if (devices.empty()) {
    choice.explanation =
        "no Vulkan device found: install a GPU driver or Mesa's lavapipe (apt-get install mesa-vulkan-drivers)";
    return choice;
  }
  int best_preference = -1;
  const std::string wanted = lower(requested_name);
  for (size_t i = 0; i < devices.size(); ++i) {
    const DeviceFacts& device = devices[i];
    const std::string label = "'" + device.name + "' (" + device_type_name(device.type) + ")";
    if (!wanted.empty() && lower(device.name).find(wanted) == std::string::npos) {
      why << "\n  " << label << ": name does not match " << requested_by << " '" << requested_name << "'";
      continue;
    }
    if (const std::string reason = rejection_reason(device); !reason.empty()) {
      why << "\n  " << label << ": " << reason;
      continue;
    }
    if (preference(device.type) > best_preference) {
      best_preference = preference(device.type);
      choice.index = i;
    }
  }
  if (!choice.index) {
    choice.explanation = "no Vulkan device fits:" + why.str();
  } else {
    const DeviceFacts& chosen = devices[*choice.index];
    choice.explanation = "using '" + chosen.name + "' (" + device_type_name(chosen.type) + ")";
  }
  return choice;
}

}  // namespace rt::vk
