#pragma once
// Frame capture through RenderDoc's in-app API, headless. Works when the process runs under
// `renderdoccmd capture` (RenderDoc already injected) or when librenderdoc.so can be loaded
// (REMOTETOUCH_RENDERDOC_LIBRARY=PATH names another copy);
// otherwise it says why no capture can be taken. Must be constructed before the Context, since
// RenderDoc hooks Vulkan when the instance is created.
#include <vulkan/vulkan.h>

#include <string>

struct RENDERDOC_API_1_6_0;

namespace rt::vk {

class RenderDocCapture {
 public:
  // load_if_absent: load librenderdoc.so when RenderDoc was not injected (only when a capture
  // was asked for: loading it hooks the whole process). file_prefix: where captures go, e.g.
  // "out/demo/capture/remotetouch"; kept as RenderDoc set it when injected by renderdoccmd.
  RenderDocCapture(bool load_if_absent, const std::string& file_prefix);

  bool available() const { return api_ != nullptr; }
  const std::string& why_unavailable() const { return why_unavailable_; }

  // title: what the capture shows, as RenderDoc lists it (empty: RenderDoc's own name).
  void begin_frame(VkInstance instance, const std::string& title = "");
  // Ends the capture started by begin_frame; returns the path of the written .rdc file.
  std::string end_frame(VkInstance instance);

 private:
  RENDERDOC_API_1_6_0* api_ = nullptr;
  std::string why_unavailable_;
};

}  // namespace rt::vk
