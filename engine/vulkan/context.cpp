#include "vulkan/context.h"

#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

#include "vulkan/check.h"
#include "vulkan/device_selection.h"
#include "vulkan/vk_struct.h"

namespace rt::vk {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr uint64_t kWaitTimeoutNs = 120'000'000'000ull;  // a stuck GPU fails loudly instead of hanging

// Under AddressSanitizer: the driver and layers the loader opened stay loaded until exit, so that
// what they keep allocated is reported with their names (and suppressed as theirs,
// tests/sanitizer/lsan.supp) rather than from an unloaded, nameless module.
void keep_loaded_libraries_for_leak_reports() {
#if defined(__SANITIZE_ADDRESS__)
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) {
        if (info->dlpi_name && info->dlpi_name[0] != '\0') dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        return 0;
      },
      nullptr);
#endif
}

bool env_flag(const char* name) {
  const char* value = std::getenv(name);
  return value && std::strcmp(value, "") != 0 && std::strcmp(value, "0") != 0;
}

bool has_instance_layer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const auto& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

bool has_instance_extension(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
  for (const auto& extension : extensions)
    if (std::strcmp(extension.extensionName, name) == 0) return true;
  return false;
}

// Needed on every device; synchronization2 and dynamic rendering are core from 1.3 and
// extensions before.
const std::vector<const char*> kDeviceExtensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};

std::vector<const char*> device_extensions(uint32_t api_version) {
  std::vector<const char*> extensions = kDeviceExtensions;
  if (api_version < VK_API_VERSION_1_3) {
    extensions.push_back(VK_KHR_SYNCHRONIZATION_2_EXTENSION_NAME);
    extensions.push_back(VK_KHR_DYNAMIC_RENDERING_EXTENSION_NAME);
  }
  return extensions;
}

int find_queue_family(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  const VkQueueFlags wanted = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
  for (uint32_t i = 0; i < count; ++i)
    if ((families[i].queueFlags & wanted) == wanted && families[i].timestampValidBits > 0) return int(i);
  return -1;
}

DeviceFacts facts_of(VkPhysicalDevice device) {
  DeviceFacts facts;
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(device, &properties);
  facts.name = properties.deviceName;
  facts.type = properties.deviceType;
  facts.api_version = properties.apiVersion;
  facts.has_compute_queue_with_timestamps = find_queue_family(device) >= 0;

  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  for (const char* wanted : device_extensions(facts.api_version)) {
    bool found = false;
    for (const auto& extension : extensions) found |= std::strcmp(extension.extensionName, wanted) == 0;
    if (!found) facts.missing_extensions.push_back(wanted);
  }
  if (facts.api_version >= VK_API_VERSION_1_2 && facts.missing_extensions.empty()) {
    auto dynamic_rendering = vk_struct<VkPhysicalDeviceDynamicRenderingFeatures>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES);
    auto sync2 = vk_struct<VkPhysicalDeviceSynchronization2Features>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES, &dynamic_rendering);
    auto features12 = vk_struct<VkPhysicalDeviceVulkan12Features>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &sync2);
    auto features = vk_struct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12);
    vkGetPhysicalDeviceFeatures2(device, &features);
    if (!sync2.synchronization2) facts.missing_features.push_back("synchronization2");
    if (!dynamic_rendering.dynamicRendering) facts.missing_features.push_back("dynamicRendering");
    if (!features12.timelineSemaphore) facts.missing_features.push_back("timelineSemaphore");
    if (!features12.hostQueryReset) facts.missing_features.push_back("hostQueryReset");
  }
  return facts;
}

}  // namespace

VkBool32 VKAPI_PTR on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                         VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                         void* user) {
  auto* context = static_cast<Context*>(user);
  const bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  if (error) {
    context->validation_errors_++;
    if (context->error_counter_) (*context->error_counter_)++;
  }
  std::cerr << (error ? "[vulkan error] " : "[vulkan warning] ") << (data->pMessage ? data->pMessage : "") << "\n";
  return VK_FALSE;
}

ContextOptions apply_environment(ContextOptions options) {
  if (env_flag("REMOTETOUCH_VALIDATION")) options.validation = true;
  if (env_flag("REMOTETOUCH_SYNC_VALIDATION")) options.validation = options.synchronization_validation = true;
  if (const char* device = std::getenv("REMOTETOUCH_DEVICE"); device && *device) {
    options.device_name = device;
    options.device_name_source = "REMOTETOUCH_DEVICE";  // the error names what the user set
  }
  return options;
}

Context::Context(const ContextOptions& options)
    : pipeline_cache_path_(options.pipeline_cache_path),
      print_device_(options.print_device),
      presentation_(options.presentation),
      error_counter_(options.error_counter) {
  try {
    create_instance(options);
    choose_physical_device(options);
    create_device();
    load_pipeline_cache();
  } catch (...) {
    release();  // the destructor does not run when the constructor throws
    throw;
  }
}

void Context::create_instance(const ContextOptions& options) {
  std::vector<const char*> layers;
  if (options.validation) {
    if (!has_instance_layer(kValidationLayer))
      throw std::runtime_error(
          "validation requested but VK_LAYER_KHRONOS_validation is not installed (apt-get install "
          "vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
  }
  std::vector<const char*> extensions;
  const bool debug_utils = has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const std::string& name : options.surface_instance_extensions) {
    if (!has_instance_extension(name.c_str()))
      throw std::runtime_error("the Vulkan loader offers no " + name + ", which a window needs: use --display headless");
    extensions.push_back(name.c_str());
  }

  auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "remotetouch";
  app.pEngineName = "remotetouch";
  app.apiVersion = VK_API_VERSION_1_3;

  auto messenger_info = vk_struct<VkDebugUtilsMessengerCreateInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  messenger_info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = on_validation_message;
  messenger_info.pUserData = this;

  const VkValidationFeatureEnableEXT sync_validation = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  auto features = vk_struct<VkValidationFeaturesEXT>(VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT);
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync_validation;

  auto info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  if (options.validation && debug_utils) {
    // Chained so that instance creation itself is validated too.
    if (options.synchronization_validation) messenger_info.pNext = &features;
    info.pNext = &messenger_info;
  }
  RT_VK_CHECK(vkCreateInstance(&info, nullptr, &instance_));

  if (debug_utils) {
    set_object_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
    begin_label_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
    end_label_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
  }
  if (options.validation && debug_utils) {
    messenger_info.pNext = nullptr;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    RT_VK_CHECK(create(instance_, &messenger_info, nullptr, &messenger_));
  }
}

void Context::choose_physical_device(const ContextOptions& options) {
  uint32_t count = 0;
  RT_VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  RT_VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, devices.data()));
  std::vector<DeviceFacts> facts;
  for (VkPhysicalDevice device : devices) facts.push_back(facts_of(device));
  const DeviceChoice choice = choose_device(facts, options.device_name, options.device_name_source);
  if (!choice.index) throw std::runtime_error(choice.explanation);
  physical_device_ = devices[*choice.index];
  vkGetPhysicalDeviceProperties(physical_device_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory_properties_);
  queue_family_ = uint32_t(find_queue_family(physical_device_));
  if (print_device_) std::cerr << "remotetouch: " << choice.explanation << "\n";
}

void Context::create_device() {
  const float priority = 1.0f;
  auto queue_info = vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue_info.queueFamilyIndex = queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  auto dynamic_rendering =
      vk_struct<VkPhysicalDeviceDynamicRenderingFeatures>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES);
  dynamic_rendering.dynamicRendering = VK_TRUE;
  auto sync2 = vk_struct<VkPhysicalDeviceSynchronization2Features>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES, &dynamic_rendering);
  sync2.synchronization2 = VK_TRUE;
  auto features12 = vk_struct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &sync2);
  features12.timelineSemaphore = VK_TRUE;
  features12.hostQueryReset = VK_TRUE;
  auto features = vk_struct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12);

  std::vector<const char*> extensions = device_extensions(properties_.apiVersion);
  if (presentation_) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(physical_device_, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> offered(count);
    vkEnumerateDeviceExtensionProperties(physical_device_, nullptr, &count, offered.data());
    const bool has_swapchain = std::any_of(offered.begin(), offered.end(), [](const VkExtensionProperties& e) {
      return std::strcmp(e.extensionName, VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0;
    });
    if (!has_swapchain)
      throw std::runtime_error(std::string(properties_.deviceName) + " cannot present to a window (no " +
                               VK_KHR_SWAPCHAIN_EXTENSION_NAME + "): use --display headless");
    extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  }
  auto info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features);
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue_info;
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  RT_VK_CHECK(vkCreateDevice(physical_device_, &info, nullptr, &device_));
  keep_loaded_libraries_for_leak_reports();
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  push_descriptor_set_ =
      reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  if (!push_descriptor_set_) throw std::runtime_error("vkCmdPushDescriptorSetKHR is missing on the chosen device");
  // Core names on 1.3 devices, KHR names on 1.2 devices with VK_KHR_synchronization2.
  auto load = [&](const char* core, const char* khr) {
    PFN_vkVoidFunction function = vkGetDeviceProcAddr(device_, core);
    if (!function) function = vkGetDeviceProcAddr(device_, khr);
    if (!function) throw std::runtime_error(std::string(core) + " is missing on the chosen device");
    return function;
  };
  pipeline_barrier2_ = reinterpret_cast<PFN_vkCmdPipelineBarrier2>(load("vkCmdPipelineBarrier2", "vkCmdPipelineBarrier2KHR"));
  write_timestamp2_ = reinterpret_cast<PFN_vkCmdWriteTimestamp2>(load("vkCmdWriteTimestamp2", "vkCmdWriteTimestamp2KHR"));
  queue_submit2_ = reinterpret_cast<PFN_vkQueueSubmit2>(load("vkQueueSubmit2", "vkQueueSubmit2KHR"));
  begin_rendering_ = reinterpret_cast<PFN_vkCmdBeginRendering>(load("vkCmdBeginRendering", "vkCmdBeginRenderingKHR"));
  end_rendering_ = reinterpret_cast<PFN_vkCmdEndRendering>(load("vkCmdEndRendering", "vkCmdEndRenderingKHR"));

  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = queue_family_;
  RT_VK_CHECK(vkCreateCommandPool(device_, &pool_info, nullptr, &command_pool_));

  auto type_info = vk_struct<VkSemaphoreTypeCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO);
  type_info.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
  auto semaphore_info = vk_struct<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, &type_info);
  RT_VK_CHECK(vkCreateSemaphore(device_, &semaphore_info, nullptr, &timeline_));
  set_name(VK_OBJECT_TYPE_SEMAPHORE, uint64_t(timeline_), "queue timeline");
  set_name(VK_OBJECT_TYPE_DEVICE, uint64_t(device_), "remotetouch device");
  set_name(VK_OBJECT_TYPE_QUEUE, uint64_t(queue_), "graphics+compute queue");
  set_name(VK_OBJECT_TYPE_COMMAND_POOL, uint64_t(command_pool_), "command pool");
}

void Context::load_pipeline_cache() {
  std::vector<char> data;
  if (!pipeline_cache_path_.empty()) {
    std::ifstream file(pipeline_cache_path_, std::ios::binary);
    if (file) data.assign(std::istreambuf_iterator<char>(file), {});
  }
  auto info = vk_struct<VkPipelineCacheCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO);
  // The driver checks the header (vendor, device, cache UUID) and ignores data that is not its own.
  info.initialDataSize = data.size();
  info.pInitialData = data.empty() ? nullptr : data.data();
  if (vkCreatePipelineCache(device_, &info, nullptr, &pipeline_cache_) != VK_SUCCESS) {
    info.initialDataSize = 0;
    info.pInitialData = nullptr;
    RT_VK_CHECK(vkCreatePipelineCache(device_, &info, nullptr, &pipeline_cache_));
  }
  set_name(VK_OBJECT_TYPE_PIPELINE_CACHE, uint64_t(pipeline_cache_), "pipeline cache");
}

void Context::save_pipeline_cache() {
  if (pipeline_cache_path_.empty() || pipeline_cache_ == VK_NULL_HANDLE) return;
  size_t size = 0;
  if (vkGetPipelineCacheData(device_, pipeline_cache_, &size, nullptr) != VK_SUCCESS || size == 0) return;
  std::vector<char> data(size);
  if (vkGetPipelineCacheData(device_, pipeline_cache_, &size, data.data()) != VK_SUCCESS) return;
  // Written beside and renamed, so that a concurrent reader never sees half a file.
  std::error_code error;
  const std::filesystem::path path(pipeline_cache_path_);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), error);
  // The process id too: the two-site demo runs two processes of one binary, whose contexts may
  // sit at the same address, and two writers of one temporary file would rename a mix of both.
  const std::string temporary = pipeline_cache_path_ + ".tmp" + std::to_string(getpid()) + "." +
                                std::to_string(reinterpret_cast<uintptr_t>(this));
  {
    std::ofstream file(temporary, std::ios::binary);
    if (!file) return;
    file.write(data.data(), std::streamsize(size));
  }
  std::filesystem::rename(temporary, path, error);
}

Context::~Context() { release(); }

void Context::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    for (auto& retired : retired_) retired.destroy();
    retired_.clear();
    save_pipeline_cache();
    if (pipeline_cache_) vkDestroyPipelineCache(device_, pipeline_cache_, nullptr);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    if (timeline_) vkDestroySemaphore(device_, timeline_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

VkResult Context::present(const VkPresentInfoKHR& info) {
  std::lock_guard lock(mutex_);
  return vkQueuePresentKHR(queue_, &info);
}

uint64_t Context::submit(VkCommandBuffer commands) {
  std::lock_guard lock(mutex_);
  const uint64_t value = last_submitted_ + 1;
  auto command_info = vk_struct<VkCommandBufferSubmitInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO);
  command_info.commandBuffer = commands;
  auto signal = vk_struct<VkSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO);
  signal.semaphore = timeline_;
  signal.value = value;
  signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  auto info = vk_struct<VkSubmitInfo2>(VK_STRUCTURE_TYPE_SUBMIT_INFO_2);
  info.commandBufferInfoCount = 1;
  info.pCommandBufferInfos = &command_info;
  info.signalSemaphoreInfoCount = 1;
  info.pSignalSemaphoreInfos = &signal;
  RT_VK_CHECK(queue_submit2_(queue_, 1, &info, VK_NULL_HANDLE));
  last_submitted_ = value;
  return value;
}

void Context::wait(uint64_t timeline_value) {
  auto info = vk_struct<VkSemaphoreWaitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO);
  info.semaphoreCount = 1;
  info.pSemaphores = &timeline_;
  info.pValues = &timeline_value;
  const VkResult result = vkWaitSemaphores(device_, &info, kWaitTimeoutNs);
  if (result == VK_TIMEOUT) throw std::runtime_error("the GPU did not finish its work within 120 s (hung or lost)");
  RT_VK_CHECK(result);
  collect_retired();
}

void Context::wait_idle() {
  RT_VK_CHECK(vkDeviceWaitIdle(device_));
  collect_retired();
}

void Context::run_now(const std::function<void(VkCommandBuffer)>& record) {
  auto allocate = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  allocate.commandPool = command_pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  auto free_commands = [&] {
    const auto pool = lock_command_pool();
    vkFreeCommandBuffers(device_, command_pool_, 1, &commands);
  };
  try {
    uint64_t done = 0;
    {
      const auto pool = lock_command_pool();
      RT_VK_CHECK(vkAllocateCommandBuffers(device_, &allocate, &commands));
      auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
      begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
      RT_VK_CHECK(vkBeginCommandBuffer(commands, &begin));
      record(commands);
      RT_VK_CHECK(vkEndCommandBuffer(commands));
      done = submit(commands);
    }
    wait(done);
  } catch (...) {
    vkDeviceWaitIdle(device_);
    if (commands) free_commands();
    throw;
  }
  free_commands();
}

void Context::retire(std::function<void()> destroy) {
  std::lock_guard lock(mutex_);
  retired_.push_back({last_submitted_, std::move(destroy)});
}

void Context::collect_retired() {
  uint64_t completed = 0;
  RT_VK_CHECK(vkGetSemaphoreCounterValue(device_, timeline_, &completed));
  std::vector<std::function<void()>> ready;
  {
    std::lock_guard lock(mutex_);
    auto keep = retired_.begin();
    for (auto& retired : retired_) {
      if (retired.after_value <= completed) ready.push_back(std::move(retired.destroy));
      else *keep++ = std::move(retired);
    }
    retired_.erase(keep, retired_.end());
  }
  for (auto& destroy : ready) destroy();  // in release order: a view goes before its image
}

uint32_t Context::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted) const {
  for (uint32_t i = 0; i < memory_properties_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (memory_properties_.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  throw std::runtime_error("no memory type with the properties needed (" + std::to_string(wanted) + ")");
}

void Context::set_name(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!set_object_name_ || handle == 0) return;
  auto info = vk_struct<VkDebugUtilsObjectNameInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT);
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  set_object_name_(device_, &info);
}

void Context::begin_label(VkCommandBuffer commands, const std::string& label) const {
  if (!begin_label_) return;
  auto info = vk_struct<VkDebugUtilsLabelEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT);
  info.pLabelName = label.c_str();
  begin_label_(commands, &info);
}

void Context::end_label(VkCommandBuffer commands) const {
  if (end_label_) end_label_(commands);
}

void Context::pipeline_barrier(VkCommandBuffer commands, const VkDependencyInfo& dependency) const {
  pipeline_barrier2_(commands, &dependency);
}

void Context::write_timestamp(VkCommandBuffer commands, VkQueryPool pool, uint32_t query) const {
  write_timestamp2_(commands, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool, query);
}

void Context::begin_rendering(VkCommandBuffer commands, const VkRenderingInfo& info) const {
  begin_rendering_(commands, &info);
}

void Context::end_rendering(VkCommandBuffer commands) const { end_rendering_(commands); }

void Context::push_descriptor_set(VkCommandBuffer commands, VkPipelineBindPoint bind_point, VkPipelineLayout layout,
                                  uint32_t set, uint32_t count, const VkWriteDescriptorSet* writes) const {
  push_descriptor_set_(commands, bind_point, layout, set, count, writes);
}

}  // namespace rt::vk
