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

TEST_CASE("an unfit device is skipped with its reasons", "[device]") {
  DeviceFacts old_gpu = device("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old_gpu.api_version = VK_API_VERSION_1_1;
  old_gpu.missing_extensions = {"VK_KHR_push_descriptor"};
  const auto choice = choose_device({old_gpu, lavapipe}, "");
  REQUIRE(choice.index);
  CHECK(*choice.index == 1);
}

TEST_CASE("when nothing fits, every device says why", "[device]") {
  DeviceFacts old_gpu = device("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old_gpu.api_version = VK_API_VERSION_1_1;
  DeviceFacts no_queue = device("Odd device", VK_PHYSICAL_DEVICE_TYPE_OTHER);
  no_queue.has_compute_queue_with_timestamps = false;
  no_queue.missing_features = {"synchronization2"};
  const auto choice = choose_device({old_gpu, no_queue, lavapipe}, "gpu");
  CHECK_FALSE(choice.index);
  CHECK_THAT(choice.explanation, Catch::Contains("Old GPU") && Catch::Contains("needs 1.2"));
  CHECK_THAT(choice.explanation, Catch::Contains("Odd device") && Catch::Contains("does not match"));
  CHECK_THAT(choice.explanation, Catch::Contains("llvmpipe") && Catch::Contains("does not match --device 'gpu'"));
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
