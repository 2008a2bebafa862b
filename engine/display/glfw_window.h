#pragma once
// A site's window (GLFW): created, polled and closed on the main thread, as GLFW requires; its key
// presses become commands that the display thread takes, so presenting never waits for events
// and events never wait for the GPU.
#include <vulkan/vulkan.h>

#include <atomic>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

struct GLFWwindow;

namespace rt::display {

struct WindowOptions {
  std::string title = "RemoteTouch";
  uint32_t width = 1280, height = 720;  // the screen's pixel size from the site file
  int monitor = -1;                     // full screen on this monitor (0 = primary); -1 = windowed
};

enum class WindowCommand {
  Quit,        // Esc, or the window closed
  Pause,       // P: the picture holds still (the session goes on)
  Screenshot,  // S
  View1, View2, View3, View4, View5, View6, View7, View8,  // F1-F8
};

// The debug view a function key selects (0 for F1), or -1 for another command.
int view_index(WindowCommand command);

class GlfwWindow {
 public:
  // Starts GLFW (main thread) and returns the instance extensions a window's surface needs. Throws
  // saying why when there is no display to open a window on.
  static std::vector<std::string> surface_instance_extensions();

  explicit GlfwWindow(const WindowOptions& options);  // main thread
  ~GlfwWindow();
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  // Main thread: handles pending events (keys, resize, close) without waiting.
  void poll();
  // Any thread: the commands since the last call, oldest first.
  std::vector<WindowCommand> take_commands();
  // Any thread: what the main thread last saw; 0 x 0 while minimised.
  VkExtent2D framebuffer_size() const;
  bool quit_requested() const { return quit_requested_; }
  // Any thread (GLFW allows it): a new surface on this window's instance.
  VkSurfaceKHR create_surface(VkInstance instance) const;
  const WindowOptions& options() const { return options_; }
  std::string description() const;

 private:
  static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
  void push(WindowCommand command);

  WindowOptions options_;
  GLFWwindow* window_ = nullptr;
  std::string monitor_name_;
  mutable std::mutex mutex_;
  std::deque<WindowCommand> commands_;  // bounded: a held key cannot grow it without end
  std::atomic<uint32_t> framebuffer_width_{0}, framebuffer_height_{0};
  std::atomic<bool> quit_requested_{false};
};

}  // namespace rt::display
