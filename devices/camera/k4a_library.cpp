#include "camera/k4a_library.h"

#include <dlfcn.h>

#include <cstdlib>

namespace rt::camera::k4a {

namespace {

constexpr const char* kLibraryFile = "libk4a.so.1.4";

std::string install_hint() {
  return std::string("install Microsoft's Azure Kinect SDK (Azure Kinect DK) or Orbbec's K4A wrapper "
                     "(OrbbecSDK-K4A-Wrapper, Femto Bolt / Mega), which both provide ") +
         kLibraryFile + ", and add the folder holding it to LD_LIBRARY_PATH (or name the file in REMOTETOUCH_K4A_LIBRARY)";
}

}  // namespace

Library::~Library() {
  if (handle) dlclose(handle);
}

std::string k4a_library_name() {
  const char* chosen = std::getenv("REMOTETOUCH_K4A_LIBRARY");
  return chosen && *chosen ? chosen : kLibraryFile;
}

std::shared_ptr<const Library> load_k4a_library() {
  auto library = std::make_shared<Library>();
  library->path = k4a_library_name();
  library->handle = dlopen(library->path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!library->handle) {
    const char* why = dlerror();
    throw LiveError("live k4a cameras need the k4a library, and '" + library->path + "' could not be loaded (" +
                    (why ? why : "unknown reason") + "): " + install_hint());
  }
  const auto bind = [&](auto& function, const char* symbol) {
    dlerror();
    void* address = dlsym(library->handle, symbol);
    if (!address)
      throw LiveError("'" + library->path + "' has no function " + symbol + ": it is not the k4a 1.4 library; " +
                      install_hint());
    function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(address);
  };
  bind(library->device_get_installed_count, "k4a_device_get_installed_count");
  bind(library->device_open, "k4a_device_open");
  bind(library->device_get_serialnum, "k4a_device_get_serialnum");
  bind(library->device_get_raw_calibration, "k4a_device_get_raw_calibration");
  bind(library->device_start_cameras, "k4a_device_start_cameras");
  bind(library->device_get_capture, "k4a_device_get_capture");
  bind(library->capture_get_color_image, "k4a_capture_get_color_image");
  bind(library->capture_get_depth_image, "k4a_capture_get_depth_image");
  bind(library->image_get_buffer, "k4a_image_get_buffer");
  bind(library->image_get_size, "k4a_image_get_size");
  bind(library->image_get_width_pixels, "k4a_image_get_width_pixels");
  bind(library->image_get_height_pixels, "k4a_image_get_height_pixels");
  bind(library->image_get_stride_bytes, "k4a_image_get_stride_bytes");
  bind(library->image_get_device_timestamp_usec, "k4a_image_get_device_timestamp_usec");
  bind(library->image_get_format, "k4a_image_get_format");
  bind(library->image_release, "k4a_image_release");
  bind(library->capture_release, "k4a_capture_release");
  bind(library->device_stop_cameras, "k4a_device_stop_cameras");
  bind(library->device_close, "k4a_device_close");
  return library;
}

}  // namespace rt::camera::k4a
