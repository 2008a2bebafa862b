#include "vulkan/renderdoc_capture.h"

#include <dlfcn.h>
#include <renderdoc_app.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace rt::vk {

RenderDocCapture::RenderDocCapture(bool load_if_absent, const std::string& file_prefix) {
  // Already in the process when started by `renderdoccmd capture` or the RenderDoc UI.
  void* library = dlopen("librenderdoc.so", RTLD_NOW | RTLD_NOLOAD);
  const bool injected = library != nullptr;
  // REMOTETOUCH_RENDERDOC_LIBRARY names another build of RenderDoc (e.g. one under /opt).
  const char* override_path = std::getenv("REMOTETOUCH_RENDERDOC_LIBRARY");
  const std::string library_path = override_path && *override_path ? override_path : "librenderdoc.so";
  if (!library && load_if_absent) {
    library = dlopen(library_path.c_str(), RTLD_NOW);
    // The loader enables RenderDoc's implicit Vulkan layer only with this variable set, and it
    // must be set before the instance is created.
    if (library) setenv("ENABLE_VULKAN_RENDERDOC_CAPTURE", "1", 1);
  }
  if (!library) {
    const char* error = dlerror();
    why_unavailable_ = "RenderDoc is not loaded: run under `renderdoccmd capture`, or install librenderdoc (apt-get "
                       "install librenderdoc) or point REMOTETOUCH_RENDERDOC_LIBRARY at librenderdoc.so" +
                       (error ? std::string(" (") + error + ")" : "");
    return;
  }
  auto get_api = reinterpret_cast<pRENDERDOC_GetAPI>(dlsym(library, "RENDERDOC_GetAPI"));
  void* api = nullptr;
  if (!get_api || !get_api(eRENDERDOC_API_Version_1_4_1, &api) || !api) {
    why_unavailable_ = "librenderdoc.so was loaded but does not offer the in-app API 1.4.1";
    return;
  }
  api_ = static_cast<RENDERDOC_API_1_6_0*>(api);
  // RenderDoc mutes validation messages by default; tests and users need to see them.
  api_->SetCaptureOptionU32(eRENDERDOC_Option_DebugOutputMute, 0);
  if (!injected && !file_prefix.empty()) {
    std::filesystem::create_directories(std::filesystem::path(file_prefix).parent_path());
    api_->SetCaptureFilePathTemplate(file_prefix.c_str());
  }
}

void RenderDocCapture::begin_frame(VkInstance instance, const std::string& title) {
  if (!api_) throw std::logic_error("begin_frame without RenderDoc: " + why_unavailable_);
  api_->StartFrameCapture(RENDERDOC_DEVICEPOINTER_FROM_VKINSTANCE(instance), nullptr);
  if (!title.empty()) api_->SetCaptureTitle(title.c_str());
}

std::string RenderDocCapture::end_frame(VkInstance instance) {
  if (!api_) throw std::logic_error("end_frame without RenderDoc: " + why_unavailable_);
  if (!api_->EndFrameCapture(RENDERDOC_DEVICEPOINTER_FROM_VKINSTANCE(instance), nullptr))
    throw std::runtime_error("RenderDoc did not write the capture (EndFrameCapture failed)");
  const uint32_t index = api_->GetNumCaptures() - 1;
  uint32_t length = 0;
  if (!api_->GetCapture(index, nullptr, &length, nullptr) || length == 0) return "(capture path unknown)";
  std::vector<char> path(length + 1, '\0');
  api_->GetCapture(index, path.data(), &length, nullptr);
  return path.data();
}

}  // namespace rt::vk
