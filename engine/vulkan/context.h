#pragma once
// The Vulkan instance, the chosen device, its one queue and the timeline that orders every
// submission. Owns deferred destruction: a handle released while the GPU may still use it is
// destroyed once the timeline shows that all work submitted before its release has finished.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace rt::vk {

struct ContextOptions {
  std::string device_name;                  // --device: substring of the device name; empty = automatic
  std::string device_name_source = "--device";  // what set device_name, for errors (or REMOTETOUCH_DEVICE)
  bool validation = false;                  // Khronos validation layer; errors are counted
  bool synchronization_validation = false;  // also its synchronization checks
  bool print_device = true;                 // say on stderr which device was chosen
  // Pipeline cache file (lavapipe JIT-compiles every pipeline); empty = no cache on disk.
  std::string pipeline_cache_path;
  // Also counts validation errors here; it may outlive the context, so that errors raised while
  // the device is destroyed (leaked objects) are seen too.
  std::atomic<uint32_t>* error_counter = nullptr;
  // For a window: the instance extensions its surface needs (from GLFW), and VK_KHR_swapchain on
  // the device. Empty and false for headless runs, which then work where no display exists.
  std::vector<std::string> surface_instance_extensions;
  bool presentation = false;
};

// Reads REMOTETOUCH_VALIDATION=1, REMOTETOUCH_SYNC_VALIDATION=1 and REMOTETOUCH_DEVICE=NAME
// on top of `options` (the environment wins where set), so that any run can be checked.
ContextOptions apply_environment(ContextOptions options);

class Context {
 public:
  explicit Context(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_device_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  VkCommandPool command_pool() const { return command_pool_; }
  // The command pool and every command buffer from it are externally synchronized (Vulkan spec):
  // hold this while allocating, recording or freeing one, from whichever thread.
  [[nodiscard]] std::unique_lock<std::recursive_mutex> lock_command_pool() const {
    return std::unique_lock(command_pool_mutex_);
  }
  VkPipelineCache pipeline_cache() const { return pipeline_cache_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  std::string device_name() const { return properties_.deviceName; }
  bool is_cpu_device() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }

  // Submits on the queue and returns the timeline value that signals its completion.
  uint64_t submit(VkCommandBuffer commands);
  // Presents on the queue, ordered with the submissions (the queue is externally synchronized).
  VkResult present(const VkPresentInfoKHR& info);
  void wait(uint64_t timeline_value);
  void wait_idle();
  // Records with `record`, submits and waits: for uploads, readbacks and tests.
  void run_now(const std::function<void(VkCommandBuffer)>& record);

  // Destroys `destroy` once the GPU has finished all work submitted so far.
  void retire(std::function<void()> destroy);
  void collect_retired();

  uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted) const;

  // Debug utils: names in validation messages and captures, labels around passes.
  void set_name(VkObjectType type, uint64_t handle, const std::string& name) const;
  void begin_label(VkCommandBuffer commands, const std::string& label) const;
  void end_label(VkCommandBuffer commands) const;
  // synchronization2 through whichever entry points the device has (core 1.3 or KHR).
  void pipeline_barrier(VkCommandBuffer commands, const VkDependencyInfo& dependency) const;
  void write_timestamp(VkCommandBuffer commands, VkQueryPool pool, uint32_t query) const;
  void begin_rendering(VkCommandBuffer commands, const VkRenderingInfo& info) const;
  void end_rendering(VkCommandBuffer commands) const;
  void push_descriptor_set(VkCommandBuffer commands, VkPipelineBindPoint bind_point, VkPipelineLayout layout,
                           uint32_t set, uint32_t count, const VkWriteDescriptorSet* writes) const;

  // Validation messages of severity ERROR seen so far (0 when validation is off).
  uint32_t validation_errors() const { return validation_errors_.load(); }
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }

 private:
  void release();
  void create_instance(const ContextOptions& options);
  void choose_physical_device(const ContextOptions& options);
  void create_device();
  void load_pipeline_cache();
  void save_pipeline_cache();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkSemaphore timeline_ = VK_NULL_HANDLE;
  VkPipelineCache pipeline_cache_ = VK_NULL_HANDLE;
  std::string pipeline_cache_path_;
  bool print_device_ = true;
  bool presentation_ = false;

  PFN_vkSetDebugUtilsObjectNameEXT set_object_name_ = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT begin_label_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT end_label_ = nullptr;
  PFN_vkCmdPushDescriptorSetKHR push_descriptor_set_ = nullptr;
  PFN_vkCmdPipelineBarrier2 pipeline_barrier2_ = nullptr;
  PFN_vkCmdWriteTimestamp2 write_timestamp2_ = nullptr;
  PFN_vkQueueSubmit2 queue_submit2_ = nullptr;
  PFN_vkCmdBeginRendering begin_rendering_ = nullptr;
  PFN_vkCmdEndRendering end_rendering_ = nullptr;

  mutable std::recursive_mutex command_pool_mutex_;
  std::mutex mutex_;  // guards the fields below: submissions and retirement may come from any thread
  uint64_t last_submitted_ = 0;
  struct Retired {
    uint64_t after_value;
    std::function<void()> destroy;
  };
  std::vector<Retired> retired_;

  std::atomic<uint32_t> validation_errors_{0};
  std::atomic<uint32_t>* error_counter_ = nullptr;
  friend VkBool32 VKAPI_PTR on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT*, void*);
};

}  // namespace rt::vk
