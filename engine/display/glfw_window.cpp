#include "display/glfw_window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <stdexcept>

namespace rt::display {
namespace {

constexpr size_t kMaxPendingCommands = 64;

std::string last_glfw_error() {
  const char* text = nullptr;
  const int code = glfwGetError(&text);
  if (code == GLFW_NO_ERROR) return "no reason given";
  return text ? std::string(text) : "GLFW error " + std::to_string(code);
}

// GLFW is started once per process and stays up until it ends: windows come and go on top.
void start_glfw() {
  static const bool started = [] {
    if (!glfwInit())
      throw std::runtime_error("no display to open a window on (" + last_glfw_error() +
                               "): set DISPLAY, or use --display headless");
    return true;
  }();
  (void)started;
}

}  // namespace

int view_index(WindowCommand command) {
  const int index = int(command) - int(WindowCommand::View1);
  return index >= 0 && index < 8 ? index : -1;
}

std::vector<std::string> GlfwWindow::surface_instance_extensions() {
  start_glfw();
  if (!glfwVulkanSupported()) throw std::runtime_error("GLFW finds no Vulkan loader that can draw to a window here");
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (!names) throw std::runtime_error("no Vulkan surface extension for this display: " + last_glfw_error());
  return std::vector<std::string>(names, names + count);
}

GlfwWindow::GlfwWindow(const WindowOptions& options) : options_(options) {
  start_glfw();
  GLFWmonitor* monitor = nullptr;
  if (options.monitor >= 0) {
    int count = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&count);
    if (options.monitor >= count)
      throw std::invalid_argument("--monitor " + std::to_string(options.monitor) + ": this display has " +
                                  std::to_string(count) + " monitor" + (count == 1 ? "" : "s") + " (0 to " +
                                  std::to_string(count - 1) + ")");
    monitor = monitors[options.monitor];
    monitor_name_ = glfwGetMonitorName(monitor) ? glfwGetMonitorName(monitor) : "unnamed";
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  window_ = glfwCreateWindow(int(options.width), int(options.height), options.title.c_str(), monitor, nullptr);
  if (!window_) throw std::runtime_error("cannot open a window: " + last_glfw_error());
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, on_key);
  poll();
}

GlfwWindow::~GlfwWindow() {
  if (window_) glfwDestroyWindow(window_);
}

void GlfwWindow::on_key(GLFWwindow* window, int key, int, int action, int) {
  if (action != GLFW_PRESS) return;
  auto* self = static_cast<GlfwWindow*>(glfwGetWindowUserPointer(window));
  if (key == GLFW_KEY_ESCAPE) self->push(WindowCommand::Quit);
  else if (key == GLFW_KEY_P) self->push(WindowCommand::Pause);
  else if (key == GLFW_KEY_S) self->push(WindowCommand::Screenshot);
  else if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F8)
    self->push(WindowCommand(int(WindowCommand::View1) + (key - GLFW_KEY_F1)));
}

void GlfwWindow::push(WindowCommand command) {
  if (command == WindowCommand::Quit) quit_requested_ = true;
  std::lock_guard lock(mutex_);
  if (commands_.size() >= kMaxPendingCommands) commands_.pop_front();
  commands_.push_back(command);
}

void GlfwWindow::poll() {
  glfwPollEvents();
  if (glfwWindowShouldClose(window_)) quit_requested_ = true;
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  framebuffer_width_ = uint32_t(std::max(width, 0));
  framebuffer_height_ = uint32_t(std::max(height, 0));
}

std::vector<WindowCommand> GlfwWindow::take_commands() {
  std::lock_guard lock(mutex_);
  std::vector<WindowCommand> taken(commands_.begin(), commands_.end());
  commands_.clear();
  return taken;
}

VkExtent2D GlfwWindow::framebuffer_size() const { return {framebuffer_width_.load(), framebuffer_height_.load()}; }

VkSurfaceKHR GlfwWindow::create_surface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  const VkResult result = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
  if (result != VK_SUCCESS)
    throw std::runtime_error("cannot make a Vulkan surface of the window (VkResult " + std::to_string(int(result)) +
                             "): " + last_glfw_error());
  return surface;
}

std::string GlfwWindow::description() const {
  const std::string size = std::to_string(options_.width) + "x" + std::to_string(options_.height);
  return options_.monitor >= 0 ? "full screen on monitor " + std::to_string(options_.monitor) + " (" + monitor_name_ + "), " + size
                               : "windowed, " + size;
}

}  // namespace rt::display
