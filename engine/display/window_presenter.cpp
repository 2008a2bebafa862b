#include "display/window_presenter.h"

#include <algorithm>
#include <stdexcept>

#include "vulkan/check.h"
#include "vulkan/vk_struct.h"

namespace rt::display {
namespace {

// How long to wait for a swapchain image: a frame that finds none free is skipped, not queued.
constexpr uint64_t kAcquireTimeoutNs = 100'000'000;

std::string result_name(VkResult result) { return "VkResult " + std::to_string(int(result)); }

[[noreturn]] void device_lost(const char* during) {
  throw std::runtime_error(std::string("the GPU was lost while ") + during +
                           " (VK_ERROR_DEVICE_LOST): the window cannot go on; the files written so far are kept");
}

// The swapchain image's own barrier: it is not a resource of the frame graph, which sees only
// the view it is blitted from.
void transition(const vk::Context& context, VkCommandBuffer commands, VkImage image, VkImageLayout from, VkImageLayout to,
                VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages,
                VkAccessFlags2 dst_access) {
  auto barrier = vk::vk_struct<VkImageMemoryBarrier2>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2);
  barrier.srcStageMask = src_stages;
  barrier.srcAccessMask = src_access;
  barrier.dstStageMask = dst_stages;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  auto dependency = vk::vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dependency.imageMemoryBarrierCount = 1;
  dependency.pImageMemoryBarriers = &barrier;
  context.pipeline_barrier(commands, dependency);
}

}  // namespace

PresentMode parse_present_mode(const std::string& text) {
  if (text == "fifo") return PresentMode::Fifo;
  if (text == "mailbox") return PresentMode::Mailbox;
  throw std::invalid_argument("--present-mode must be fifo or mailbox, not '" + text + "'");
}

struct WindowPresenter::Swapchain {
  VkDevice device = VK_NULL_HANDLE;
  VkSwapchainKHR swapchain = VK_NULL_HANDLE;
  std::vector<VkImage> images;
  VkFence acquired = VK_NULL_HANDLE;
  bool out_of_date = false;
  ~Swapchain() {
    if (acquired) vkDestroyFence(device, acquired, nullptr);
    if (swapchain) vkDestroySwapchainKHR(device, swapchain, nullptr);
  }
};

WindowPresenter::WindowPresenter(vk::Context& context, const GlfwWindow& window, PresentMode mode)
    : context_(context), window_(window), wanted_mode_(mode), view_pass_(context) {
  make_surface();
}

WindowPresenter::~WindowPresenter() {
  context_.wait_idle();
  graph_.reset();
  swapchain_.reset();
  if (surface_) vkDestroySurfaceKHR(context_.instance(), surface_, nullptr);
}

void WindowPresenter::make_surface() {
  if (surface_) {
    context_.wait_idle();
    graph_.reset();
    swapchain_.reset();
    vkDestroySurfaceKHR(context_.instance(), surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
  }
  surface_ = window_.create_surface(context_.instance());
  VkBool32 supported = VK_FALSE;
  RT_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(context_.physical_device(), context_.queue_family(), surface_, &supported));
  if (!supported)
    throw std::runtime_error(context_.device_name() + " cannot present to this window from its compute queue: use --display headless");
}

void WindowPresenter::make_swapchain(VkExtent2D size) {
  VkSurfaceCapabilitiesKHR caps{};
  RT_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(context_.physical_device(), surface_, &caps));
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == UINT32_MAX)  // the surface takes the swapchain's size
    extent = {std::clamp(size.width, caps.minImageExtent.width, caps.maxImageExtent.width),
              std::clamp(size.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
  context_.wait_idle();
  graph_.reset();
  if (extent.width == 0 || extent.height == 0) {
    swapchain_.reset();
    extent_ = extent;
    return;
  }
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
    throw std::runtime_error("the window's surface takes no transfers into its images: this device cannot show the window");

  uint32_t count = 0;
  RT_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(context_.physical_device(), surface_, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  RT_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(context_.physical_device(), surface_, &count, formats.data()));
  if (formats.empty()) throw std::runtime_error("the window's surface offers no image format");
  // UNORM, not SRGB: the screen shows the composite's values as the PNGs hold them.
  VkSurfaceFormatKHR format = formats.front();
  for (const VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}) {
    const auto found = std::find_if(formats.begin(), formats.end(), [&](const VkSurfaceFormatKHR& f) { return f.format == wanted; });
    if (found != formats.end()) {
      format = *found;
      break;
    }
  }
  RT_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(context_.physical_device(), surface_, &count, nullptr));
  std::vector<VkPresentModeKHR> modes(count);
  RT_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(context_.physical_device(), surface_, &count, modes.data()));
  const bool mailbox = wanted_mode_ == PresentMode::Mailbox &&
                       std::find(modes.begin(), modes.end(), VK_PRESENT_MODE_MAILBOX_KHR) != modes.end();
  mode_ = mailbox ? VK_PRESENT_MODE_MAILBOX_KHR : VK_PRESENT_MODE_FIFO_KHR;  // FIFO: always there

  auto info = vk::vk_struct<VkSwapchainCreateInfoKHR>(VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR);
  info.surface = surface_;
  info.minImageCount = std::max(caps.minImageCount, mailbox ? 3u : 2u);
  if (caps.maxImageCount > 0) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                            ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                            : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
  info.presentMode = mode_;
  info.clipped = VK_TRUE;
  info.oldSwapchain = swapchain_ ? swapchain_->swapchain : VK_NULL_HANDLE;

  auto made = std::make_unique<Swapchain>();
  made->device = context_.device();
  RT_VK_CHECK(vkCreateSwapchainKHR(context_.device(), &info, nullptr, &made->swapchain));
  swapchain_ = std::move(made);  // the old one goes now that the new one replaced it
  RT_VK_CHECK(vkGetSwapchainImagesKHR(context_.device(), swapchain_->swapchain, &count, nullptr));
  swapchain_->images.resize(count);
  RT_VK_CHECK(vkGetSwapchainImagesKHR(context_.device(), swapchain_->swapchain, &count, swapchain_->images.data()));
  auto fence_info = vk::vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  RT_VK_CHECK(vkCreateFence(context_.device(), &fence_info, nullptr, &swapchain_->acquired));
  for (size_t i = 0; i < swapchain_->images.size(); ++i)
    context_.set_name(VK_OBJECT_TYPE_IMAGE, uint64_t(swapchain_->images[i]), "swapchain image " + std::to_string(i));
  extent_ = extent;
  view_ = std::make_unique<vk::Image>(context_, vk::ImageDesc{"window view", extent.width, extent.height, PixelFormat::RGBA8});
  has_view_ = false;
  ++counts_.swapchains_made;
}

void WindowPresenter::build_graph(vk::Image& source) {
  graph_ = std::make_unique<vk::FrameGraph>(context_, "window");
  view_pass_.add_to(*graph_, source, *view_, [this] { return mapping_; });
  graph_->add_pass({
      .name = "present_blit",
      .uses = {{view_.get(), vk::access::transfer_read}},
      .record =
          [this](VkCommandBuffer commands) {
            const VkImage target = swapchain_->images[image_index_];
            transition(context_, commands, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                       VK_ACCESS_2_TRANSFER_WRITE_BIT);
            // A blit, not a copy: the swapchain's format may order the channels otherwise (BGRA).
            VkImageBlit region{};
            region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.srcOffsets[1] = region.dstOffsets[1] = {int32_t(extent_.width), int32_t(extent_.height), 1};
            vkCmdBlitImage(commands, view_->image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_NEAREST);
            transition(context_, commands, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                       VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE,
                       VK_ACCESS_2_NONE);
          },
  });
  graph_source_ = &source;
}

bool WindowPresenter::present(vk::Image& source, const passes::DisplayViewMapping& mapping) {
  const VkExtent2D size = window_.framebuffer_size();
  if (size.width == 0 || size.height == 0) {
    ++counts_.skipped_minimised;
    return false;
  }
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (!swapchain_ || swapchain_->out_of_date || size.width != extent_.width || size.height != extent_.height)
      make_swapchain(size);
    if (!swapchain_) {
      ++counts_.skipped_minimised;
      return false;
    }
    const VkResult acquired = vkAcquireNextImageKHR(context_.device(), swapchain_->swapchain, kAcquireTimeoutNs,
                                                    VK_NULL_HANDLE, swapchain_->acquired, &image_index_);
    if (acquired == VK_SUCCESS || acquired == VK_SUBOPTIMAL_KHR) {
      swapchain_->out_of_date = acquired == VK_SUBOPTIMAL_KHR;
      break;
    }
    if (acquired == VK_TIMEOUT || acquired == VK_NOT_READY) {
      ++counts_.skipped_not_ready;
      return false;
    }
    if (acquired == VK_ERROR_DEVICE_LOST) device_lost("taking a window image");
    if (acquired == VK_ERROR_SURFACE_LOST_KHR) {
      ++counts_.surfaces_lost;
      make_surface();
    } else if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
      swapchain_->out_of_date = true;
    } else {
      throw std::runtime_error("cannot take a window image: " + result_name(acquired));
    }
    if (attempt == 1) {
      ++counts_.skipped_not_ready;
      return false;
    }
  }
  const VkResult waited = vkWaitForFences(context_.device(), 1, &swapchain_->acquired, VK_TRUE, kAcquireTimeoutNs * 10);
  if (waited == VK_ERROR_DEVICE_LOST) device_lost("waiting for a window image");
  RT_VK_CHECK(waited);
  RT_VK_CHECK(vkResetFences(context_.device(), 1, &swapchain_->acquired));

  if (!graph_ || graph_source_ != &source) build_graph(source);
  mapping_ = mapping;
  graph_->run();  // waits: the image is complete before it is presented, so no semaphore is needed

  auto info = vk::vk_struct<VkPresentInfoKHR>(VK_STRUCTURE_TYPE_PRESENT_INFO_KHR);
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain_->swapchain;
  info.pImageIndices = &image_index_;
  const VkResult presented = context_.present(info);
  if (presented == VK_ERROR_DEVICE_LOST) device_lost("presenting");
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) swapchain_->out_of_date = true;
  else if (presented == VK_ERROR_SURFACE_LOST_KHR) {
    ++counts_.surfaces_lost;
    make_surface();
    return false;
  } else if (presented != VK_SUCCESS) {
    throw std::runtime_error("cannot present the window image: " + result_name(presented));
  }
  has_view_ = true;
  ++counts_.presented;
  return true;
}

HostImage WindowPresenter::last_view() {
  if (!has_view_ || !view_) return {};
  return vk::download(context_, *view_);
}

std::string WindowPresenter::present_mode_name() const {
  return mode_ == VK_PRESENT_MODE_MAILBOX_KHR ? "MAILBOX" : "FIFO";
}

}  // namespace rt::display
