#pragma once
// Shows images of the pipeline in a site's window: a debug view pass maps the chosen image into
// an rgba8 view at the window's size, a blit puts it on the swapchain's image, and the queue
// presents it; all on the GPU, without a round trip through the CPU. The swapchain is made again
// when the window changes size or its surface goes out of date or is lost; while the window is
// minimised nothing is presented. Used by one thread (the site's display), under the GPU turn.
#include <memory>
#include <string>

#include "display/glfw_window.h"
#include "passes/display_view.h"
#include "vulkan/frame_graph.h"

namespace rt::display {

enum class PresentMode { Fifo, Mailbox };  // Mailbox where the device offers it, else FIFO
PresentMode parse_present_mode(const std::string& text);  // fifo | mailbox; throws naming the choices

struct PresenterCounts {
  uint64_t presented = 0;
  uint64_t skipped_minimised = 0;    // the window had no area
  uint64_t skipped_not_ready = 0;    // no swapchain image came free in time
  uint64_t swapchains_made = 0;      // the first, and one per resize or out-of-date surface
  uint64_t surfaces_lost = 0;        // and made again
};

class WindowPresenter {
 public:
  WindowPresenter(vk::Context& context, const GlfwWindow& window, PresentMode mode);
  ~WindowPresenter();
  WindowPresenter(const WindowPresenter&) = delete;
  WindowPresenter& operator=(const WindowPresenter&) = delete;

  // Shows `source` as `mapping` says. Returns false when nothing could be presented this time
  // (minimised, no image free); throws when the device is lost.
  bool present(vk::Image& source, const passes::DisplayViewMapping& mapping);
  // The last view presented, rgba8 at the window's size, as the screen shows it; empty before one.
  HostImage last_view();

  const PresenterCounts& counts() const { return counts_; }
  std::string present_mode_name() const;  // the mode in use: FIFO or MAILBOX
  VkExtent2D extent() const { return extent_; }

 private:
  struct Swapchain;
  void make_swapchain(VkExtent2D size);
  void make_surface();
  void build_graph(vk::Image& source);

  vk::Context& context_;
  const GlfwWindow& window_;
  PresentMode wanted_mode_;
  VkPresentModeKHR mode_ = VK_PRESENT_MODE_FIFO_KHR;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  std::unique_ptr<Swapchain> swapchain_;
  VkExtent2D extent_{0, 0};
  passes::DisplayViewPass view_pass_;
  std::unique_ptr<vk::Image> view_;
  std::unique_ptr<vk::FrameGraph> graph_;
  vk::Image* graph_source_ = nullptr;
  passes::DisplayViewMapping mapping_;
  uint32_t image_index_ = 0;
  bool has_view_ = false;
  PresenterCounts counts_;
};

}  // namespace rt::display
