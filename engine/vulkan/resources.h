#pragma once
// GPU buffers and images with their memory, their debug name and their tracked state (the last
// use, from which the frame graph and the transfers derive barriers). Also samplers and command
// buffers. All move-only; destruction waits for the GPU (see handle.h).
#include <vulkan/vulkan.h>

#include <cstddef>
#include <span>
#include <string>

#include "image/host_image.h"
#include "vulkan/barriers.h"
#include "vulkan/handle.h"

namespace rt::vk {

VkFormat vulkan_format(PixelFormat format);
VkImageAspectFlags aspect_of(PixelFormat format);

struct ImageDesc {
  std::string name;
  uint32_t width = 0;
  uint32_t height = 0;
  PixelFormat format = PixelFormat::RGBA32F;
};

class Image {
 public:
  Image(Context& context, const ImageDesc& desc);

  VkImage image() const { return image_.get(); }
  VkImageView view() const { return view_.get(); }
  VkFormat format() const { return vulkan_format(desc_.format); }
  PixelFormat pixel_format() const { return desc_.format; }
  uint32_t width() const { return desc_.width; }
  uint32_t height() const { return desc_.height; }
  const std::string& name() const { return desc_.name; }
  size_t size_bytes() const { return size_t(desc_.width) * desc_.height * bytes_per_texel(desc_.format); }
  ResourceState& state() { return state_; }

 private:
  ImageDesc desc_;
  Handle<VkDeviceMemory> memory_;  // declared first, so destroyed last
  Handle<VkImage> image_;
  Handle<VkImageView> view_;
  ResourceState state_;
};

struct BufferDesc {
  std::string name;
  VkDeviceSize size = 0;
  VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  bool host_visible = false;  // mapped for the buffer's lifetime (staging, readback)
};

class Buffer {
 public:
  Buffer(Context& context, const BufferDesc& desc);

  VkBuffer buffer() const { return buffer_.get(); }
  VkDeviceSize size() const { return desc_.size; }
  const std::string& name() const { return desc_.name; }
  std::byte* mapped() const { return mapped_; }  // null unless host_visible
  ResourceState& state() { return state_; }

 private:
  BufferDesc desc_;
  Handle<VkDeviceMemory> memory_;
  Handle<VkBuffer> buffer_;
  std::byte* mapped_ = nullptr;
  ResourceState state_;
};

class Sampler {
 public:
  // Bilinear, clamped to the edge, unnormalised=false.
  Sampler(Context& context, const std::string& name, VkFilter filter = VK_FILTER_LINEAR);
  VkSampler get() const { return sampler_.get(); }

 private:
  Handle<VkSampler> sampler_;
};

class CommandBuffer {
 public:
  CommandBuffer(Context& context, const std::string& name);
  VkCommandBuffer get() const { return commands_.get(); }

 private:
  Handle<VkCommandBuffer> commands_;
};

// Records the barrier (if any) that `access` needs after the resource's last use.
void use_image(const Context& context, VkCommandBuffer commands, Image& image, const Access& access);
void use_buffer(const Context& context, VkCommandBuffer commands, Buffer& buffer, const Access& access);
VkImageMemoryBarrier2 image_barrier(const Image& image, const BarrierPlan& plan);
VkBufferMemoryBarrier2 buffer_barrier(const Buffer& buffer, const BarrierPlan& plan);

// Synchronous staging copies, for inputs, readbacks and tests.
void upload(Context& context, Image& image, const HostImage& pixels);
HostImage download(Context& context, Image& image);
void upload(Context& context, Buffer& buffer, std::span<const std::byte> bytes);
std::vector<std::byte> download(Context& context, Buffer& buffer);

}  // namespace rt::vk
