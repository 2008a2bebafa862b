// Device choice from plain device facts: prefer a GPU, fall back to lavapipe, honour --device,
// and say why each device was rejected.
#include <catch2/catch.hpp>

#include "vulkan/device_selection.h"

using namespace rt::vk;

namespace {

DeviceFacts device(const std::string& name, VkPhysicalDeviceType type) {
  DeviceFacts facts;
  facts.name = name;
  facts.type = type;
  facts.api_version = VK_API_VERSION_1_3;
  facts.has_compute_queue_with_timestamps = true;
  return facts;
}

const DeviceFacts lavapipe = device("llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU);
const DeviceFacts discrete = device("NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
const DeviceFacts integrated = device("Intel UHD", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);

}  // namespace

TEST_CASE("a discrete GPU wins over integrated and CPU devices", "[device]") {
  const auto choice = choose_device({lavapipe, integrated, discrete}, "");
  REQUIRE(choice.index);
  CHECK(*choice.index == 2);
}

TEST_CASE("an integrated GPU wins over lavapipe", "[device]") {
  const auto choice = choose_device({lavapipe, integrated}, "");
  REQUIRE(choice.index);
  CHECK(*choice.index == 1);
}

TEST_CASE("lavapipe is the fallback", "[device]") {
  const auto choice = choose_device({lavapipe}, "");
  REQUIRE(choice.index);
  CHECK(*choice.index == 0);
  CHECK_THAT(choice.explanation, Catch::Contains("CPU"));
}

TEST_CASE("--device picks by a case-insensitive part of the name", "[device]") {
  const auto choice = choose_device({discrete, lavapipe}, "LLVMPIPE");
  REQUIRE(choice.index);
  CHECK(*choice.index == 1);
}

TEST_CASE("each unfit property is a reason of its own", "[device]") {
  CHECK(rejection_reason(lavapipe).empty());
  DeviceFacts old_gpu = device("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old_gpu.api_version = VK_API_VERSION_1_1;
  CHECK(rejection_reason(old_gpu) == "supports Vulkan 1.1, needs 1.2");
  DeviceFacts no_queue = device("Odd device", VK_PHYSICAL_DEVICE_TYPE_OTHER);
  no_queue.has_compute_queue_with_timestamps = false;
  CHECK(rejection_reason(no_queue) == "no graphics+compute queue with timestamps");
  DeviceFacts few_extensions = device("Few extensions", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);
  few_extensions.missing_extensions = {"VK_KHR_push_descriptor", "VK_KHR_synchronization2"};
  CHECK(rejection_reason(few_extensions) == "lacks extensions VK_KHR_push_descriptor, VK_KHR_synchronization2");
  DeviceFacts few_features = device("Few features", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);
  few_features.missing_features = {"synchronization2"};
  CHECK(rejection_reason(few_features) == "lacks features synchronization2");
  // Version 1.2 exactly is enough.
  DeviceFacts version_1_2 = device("Vulkan 1.2", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  version_1_2.api_version = VK_API_VERSION_1_2;
  CHECK(rejection_reason(version_1_2).empty());
}

TEST_CASE("an unfit device is skipped with its reasons", "[device]") {
  DeviceFacts old_gpu = device("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old_gpu.api_version = VK_API_VERSION_1_1;
  old_gpu.missing_extensions = {"VK_KHR_push_descriptor"};
  // Every reason, in one line.
  CHECK(rejection_reason(old_gpu) == "supports Vulkan 1.1, needs 1.2, lacks extensions VK_KHR_push_descriptor");
  const auto choice = choose_device({old_gpu, lavapipe}, "");
  REQUIRE(choice.index);
  CHECK(*choice.index == 1);
  CHECK(choice.explanation == "using 'llvmpipe (LLVM 15.0.6, 256 bits)' (CPU)");
}

TEST_CASE("when nothing fits, every device says why", "[device]") {
  DeviceFacts old_gpu = device("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old_gpu.api_version = VK_API_VERSION_1_1;
  DeviceFacts no_queue = device("Odd device", VK_PHYSICAL_DEVICE_TYPE_OTHER);
  no_queue.has_compute_queue_with_timestamps = false;
  no_queue.missing_features = {"synchronization2"};
  DeviceFacts old_lavapipe = lavapipe;
  old_lavapipe.missing_extensions = {"VK_EXT_shader_atomic_float"};
  const auto choice = choose_device({old_gpu, no_queue, old_lavapipe}, "");
  CHECK_FALSE(choice.index);
  // One line per device, in order: its name, its type and all of its reasons.
  CHECK(choice.explanation ==
        "no Vulkan device fits:"
        "\n  'Old GPU' (discrete GPU): supports Vulkan 1.1, needs 1.2"
        "\n  'Odd device' (other): no graphics+compute queue with timestamps, lacks features synchronization2"
        "\n  'llvmpipe (LLVM 15.0.6, 256 bits)' (CPU): lacks extensions VK_EXT_shader_atomic_float");
}

TEST_CASE("--device: a device whose name does not match is rejected for that alone", "[device]") {
  DeviceFacts old_gpu = device("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old_gpu.api_version = VK_API_VERSION_1_1;
  const auto choice = choose_device({old_gpu, discrete, lavapipe}, "gpu");
  CHECK_FALSE(choice.index);
  CHECK(choice.explanation ==
        "no Vulkan device fits:"
        "\n  'Old GPU' (discrete GPU): supports Vulkan 1.1, needs 1.2"
        "\n  'NVIDIA H100' (discrete GPU): name does not match --device 'gpu'"
        "\n  'llvmpipe (LLVM 15.0.6, 256 bits)' (CPU): name does not match --device 'gpu'");
}

TEST_CASE("no devices at all names the package to install", "[device]") {
  const auto choice = choose_device({}, "");
  CHECK_FALSE(choice.index);
  CHECK_THAT(choice.explanation, Catch::Contains("mesa-vulkan-drivers"));
}

TEST_CASE("a name from the environment is blamed on the variable, not on --device", "[device]") {
  const auto choice = choose_device({lavapipe}, "amd", "REMOTETOUCH_DEVICE");
  CHECK_FALSE(choice.index);
  CHECK_THAT(choice.explanation, Catch::Contains("does not match REMOTETOUCH_DEVICE 'amd'") && !Catch::Contains("--device"));
}
