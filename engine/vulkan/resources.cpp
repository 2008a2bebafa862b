#include "vulkan/resources.h"

#include <cstring>
#include <stdexcept>

#include "vulkan/check.h"
#include "vulkan/vk_struct.h"

namespace rt::vk {
namespace {

Handle<VkDeviceMemory> allocate(Context& context, const VkMemoryRequirements& requirements,
                                VkMemoryPropertyFlags properties, const std::string& name) {
  auto info = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = context.find_memory_type(requirements.memoryTypeBits, properties);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  const VkResult result = vkAllocateMemory(context.device(), &info, nullptr, &memory);
  if (result != VK_SUCCESS)
    throw VulkanError("vkAllocateMemory(" + std::to_string(requirements.size) + " bytes for '" + name + "')", result);
  context.set_name(VK_OBJECT_TYPE_DEVICE_MEMORY, uint64_t(memory), name + " memory");
  return Handle<VkDeviceMemory>(context, memory);
}

void record(const Context& context, VkCommandBuffer commands, const VkImageMemoryBarrier2* image,
            const VkBufferMemoryBarrier2* buffer) {
  auto dependency = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dependency.imageMemoryBarrierCount = image ? 1 : 0;
  dependency.pImageMemoryBarriers = image;
  dependency.bufferMemoryBarrierCount = buffer ? 1 : 0;
  dependency.pBufferMemoryBarriers = buffer;
  context.pipeline_barrier(commands, dependency);
}

}  // namespace

VkFormat vulkan_format(PixelFormat format) {
  switch (format) {
    case PixelFormat::R32F: return VK_FORMAT_R32_SFLOAT;
    case PixelFormat::RGBA32F: return VK_FORMAT_R32G32B32A32_SFLOAT;
    case PixelFormat::RGBA8: return VK_FORMAT_R8G8B8A8_UNORM;
    case PixelFormat::R16U: return VK_FORMAT_R16_UINT;
    case PixelFormat::D32F: return VK_FORMAT_D32_SFLOAT;
  }
  throw std::logic_error("unknown pixel format");
}

VkImageAspectFlags aspect_of(PixelFormat format) {
  return format == PixelFormat::D32F ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

Image::Image(Context& context, const ImageDesc& desc) : desc_(desc) {
  if (desc.width == 0 || desc.height == 0)
    throw std::invalid_argument("image '" + desc.name + "' has size " + std::to_string(desc.width) + "x" +
                                std::to_string(desc.height) + "; both sides must be at least 1");
  const uint32_t max_side = context.properties().limits.maxImageDimension2D;
  if (desc.width > max_side || desc.height > max_side)
    throw std::invalid_argument("image '" + desc.name + "' is larger than the device's " + std::to_string(max_side) +
                                " pixels per side");
  auto info = vk_struct<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = vulkan_format(desc.format);
  info.extent = {desc.width, desc.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  // Every image can be a pass's storage image or render target, sampled, and copied.
  info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
               (desc.format == PixelFormat::D32F
                    ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                    : VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage image = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateImage(context.device(), &info, nullptr, &image));
  Handle<VkImage> owned(context, image);
  context.set_name(VK_OBJECT_TYPE_IMAGE, uint64_t(image), desc.name);

  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(context.device(), image, &requirements);
  memory_ = allocate(context, requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, desc.name);
  RT_VK_CHECK(vkBindImageMemory(context.device(), image, memory_.get(), 0));
  image_ = std::move(owned);

  auto view_info = vk_struct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  view_info.image = image;
  view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view_info.format = info.format;
  view_info.subresourceRange = {aspect_of(desc.format), 0, 1, 0, 1};
  VkImageView view = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateImageView(context.device(), &view_info, nullptr, &view));
  view_ = Handle<VkImageView>(context, view);
  context.set_name(VK_OBJECT_TYPE_IMAGE_VIEW, uint64_t(view), desc.name + " view");
}

Buffer::Buffer(Context& context, const BufferDesc& desc) : desc_(desc) {
  if (desc.size == 0) throw std::invalid_argument("buffer '" + desc.name + "' has size 0");
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = desc.size;
  info.usage = desc.usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateBuffer(context.device(), &info, nullptr, &buffer));
  Handle<VkBuffer> owned(context, buffer);
  context.set_name(VK_OBJECT_TYPE_BUFFER, uint64_t(buffer), desc.name);

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(context.device(), buffer, &requirements);
  const VkMemoryPropertyFlags properties = desc.host_visible
                                               ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                               : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  memory_ = allocate(context, requirements, properties, desc.name);
  RT_VK_CHECK(vkBindBufferMemory(context.device(), buffer, memory_.get(), 0));
  buffer_ = std::move(owned);
  if (desc.host_visible) {
    void* pointer = nullptr;
    RT_VK_CHECK(vkMapMemory(context.device(), memory_.get(), 0, VK_WHOLE_SIZE, 0, &pointer));
    mapped_ = static_cast<std::byte*>(pointer);
  }
}

Sampler::Sampler(Context& context, const std::string& name, VkFilter filter) {
  auto info = vk_struct<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
  info.magFilter = filter;
  info.minFilter = filter;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkSampler sampler = VK_NULL_HANDLE;
  RT_VK_CHECK(vkCreateSampler(context.device(), &info, nullptr, &sampler));
  sampler_ = Handle<VkSampler>(context, sampler);
  context.set_name(VK_OBJECT_TYPE_SAMPLER, uint64_t(sampler), name);
}

CommandBuffer::CommandBuffer(Context& context, const std::string& name) {
  auto info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  info.commandPool = context.command_pool();
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  {
    const auto pool = context.lock_command_pool();
    RT_VK_CHECK(vkAllocateCommandBuffers(context.device(), &info, &commands));
  }
  commands_ = Handle<VkCommandBuffer>(context, commands);
  context.set_name(VK_OBJECT_TYPE_COMMAND_BUFFER, uint64_t(commands), name);
}

VkImageMemoryBarrier2 image_barrier(const Image& image, const BarrierPlan& plan) {
  auto barrier = vk_struct<VkImageMemoryBarrier2>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2);
  barrier.srcStageMask = plan.src_stages;
  barrier.srcAccessMask = plan.src_access;
  barrier.dstStageMask = plan.dst_stages;
  barrier.dstAccessMask = plan.dst_access;
  barrier.oldLayout = plan.old_layout;
  barrier.newLayout = plan.new_layout;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image.image();
  barrier.subresourceRange = {aspect_of(image.pixel_format()), 0, 1, 0, 1};
  return barrier;
}

VkBufferMemoryBarrier2 buffer_barrier(const Buffer& buffer, const BarrierPlan& plan) {
  auto barrier = vk_struct<VkBufferMemoryBarrier2>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2);
  barrier.srcStageMask = plan.src_stages;
  barrier.srcAccessMask = plan.src_access;
  barrier.dstStageMask = plan.dst_stages;
  barrier.dstAccessMask = plan.dst_access;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.buffer = buffer.buffer();
  barrier.offset = 0;
  barrier.size = VK_WHOLE_SIZE;
  return barrier;
}

void use_image(const Context& context, VkCommandBuffer commands, Image& image, const Access& access) {
  if (auto plan = plan_access(image.state(), access, true)) {
    const VkImageMemoryBarrier2 barrier = image_barrier(image, *plan);
    record(context, commands, &barrier, nullptr);
  }
}

void use_buffer(const Context& context, VkCommandBuffer commands, Buffer& buffer, const Access& access) {
  if (auto plan = plan_access(buffer.state(), access, false)) {
    const VkBufferMemoryBarrier2 barrier = buffer_barrier(buffer, *plan);
    record(context, commands, nullptr, &barrier);
  }
}

void upload(Context& context, Image& image, const HostImage& pixels) {
  if (pixels.width != image.width() || pixels.height != image.height() || pixels.format != image.pixel_format())
    throw std::invalid_argument("upload to '" + image.name() + "': host image is " + std::to_string(pixels.width) + "x" +
                                std::to_string(pixels.height) + " " + format_name(pixels.format) + ", GPU image is " +
                                std::to_string(image.width()) + "x" + std::to_string(image.height()) + " " +
                                format_name(image.pixel_format()));
  const std::vector<std::byte> bytes = pack_texels(pixels);
  Buffer staging(context, {image.name() + " upload", bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true});
  std::memcpy(staging.mapped(), bytes.data(), bytes.size());
  context.run_now([&](VkCommandBuffer commands) {
    use_image(context, commands, image, access::transfer_write);
    VkBufferImageCopy region{};
    region.imageSubresource = {aspect_of(image.pixel_format()), 0, 0, 1};
    region.imageExtent = {image.width(), image.height(), 1};
    vkCmdCopyBufferToImage(commands, staging.buffer(), image.image(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  });
}

HostImage download(Context& context, Image& image) {
  Buffer staging(context, {image.name() + " readback", image.size_bytes(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, true});
  context.run_now([&](VkCommandBuffer commands) {
    use_image(context, commands, image, access::transfer_read);
    VkBufferImageCopy region{};
    region.imageSubresource = {aspect_of(image.pixel_format()), 0, 0, 1};
    region.imageExtent = {image.width(), image.height(), 1};
    vkCmdCopyImageToBuffer(commands, image.image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer(), 1, &region);
    // Device writes reach the host only through a barrier to the host stage.
    use_buffer(context, commands, staging, access::transfer_write);
    use_buffer(context, commands, staging, access::host_read);
  });
  return unpack_texels(image.width(), image.height(), image.pixel_format(), staging.mapped());
}

void upload(Context& context, Buffer& buffer, std::span<const std::byte> bytes) {
  if (bytes.size() > buffer.size())
    throw std::invalid_argument("upload of " + std::to_string(bytes.size()) + " bytes into buffer '" + buffer.name() +
                                "' of " + std::to_string(buffer.size()) + " bytes");
  Buffer staging(context, {buffer.name() + " upload", bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true});
  std::memcpy(staging.mapped(), bytes.data(), bytes.size());
  context.run_now([&](VkCommandBuffer commands) {
    use_buffer(context, commands, buffer, access::transfer_write);
    const VkBufferCopy region{0, 0, bytes.size()};
    vkCmdCopyBuffer(commands, staging.buffer(), buffer.buffer(), 1, &region);
  });
}

std::vector<std::byte> download(Context& context, Buffer& buffer) {
  Buffer staging(context, {buffer.name() + " readback", buffer.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, true});
  context.run_now([&](VkCommandBuffer commands) {
    use_buffer(context, commands, buffer, access::transfer_read);
    const VkBufferCopy region{0, 0, buffer.size()};
    vkCmdCopyBuffer(commands, buffer.buffer(), staging.buffer(), 1, &region);
    use_buffer(context, commands, staging, access::transfer_write);
    use_buffer(context, commands, staging, access::host_read);
  });
  return {staging.mapped(), staging.mapped() + buffer.size()};
}

}  // namespace rt::vk
