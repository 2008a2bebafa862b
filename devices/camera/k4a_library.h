#pragma once
// libk4a.so.1.4 loaded at run time (dlopen), so that RemoteTouch builds and runs without the
// SDK and needs it only for live cameras. REMOTETOUCH_K4A_LIBRARY names another file (the
// tests' fake library, or an SDK installed outside the loader's path).
#include <memory>
#include <stdexcept>
#include <string>

#include "camera/k4a_api.h"

namespace rt::camera::k4a {

// A live device's errors say what to install, plug in or change.
class LiveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Library {
  k4a_device_get_installed_count_fn device_get_installed_count = nullptr;
  k4a_device_open_fn device_open = nullptr;
  k4a_device_get_serialnum_fn device_get_serialnum = nullptr;
  k4a_device_get_raw_calibration_fn device_get_raw_calibration = nullptr;
  k4a_device_start_cameras_fn device_start_cameras = nullptr;
  k4a_device_get_capture_fn device_get_capture = nullptr;
  k4a_capture_get_image_fn capture_get_color_image = nullptr;
  k4a_capture_get_image_fn capture_get_depth_image = nullptr;
  k4a_image_get_buffer_fn image_get_buffer = nullptr;
  k4a_image_get_size_fn image_get_size = nullptr;
  k4a_image_get_int_fn image_get_width_pixels = nullptr;
  k4a_image_get_int_fn image_get_height_pixels = nullptr;
  k4a_image_get_int_fn image_get_stride_bytes = nullptr;
  k4a_image_get_device_timestamp_usec_fn image_get_device_timestamp_usec = nullptr;
  k4a_image_get_format_fn image_get_format = nullptr;
  k4a_image_release_fn image_release = nullptr;
  k4a_capture_release_fn capture_release = nullptr;
  k4a_device_fn device_stop_cameras = nullptr;
  k4a_device_fn device_close = nullptr;

  std::string path;  // what was loaded, for messages
  void* handle = nullptr;
  ~Library();
};

// The library's file: REMOTETOUCH_K4A_LIBRARY when set, else "libk4a.so.1.4" (the loader's path).
std::string k4a_library_name();
// Loads it and every function the backend calls. Throws LiveError saying what to install when the
// file is missing or is not the k4a 1.4 library.
std::shared_ptr<const Library> load_k4a_library();

}  // namespace rt::camera::k4a
