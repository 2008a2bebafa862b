#pragma once
// The few types and functions of the k4a C API (libk4a.so.1.4: Microsoft's Azure Kinect SDK, or
// Orbbec's K4A wrapper for the Femto devices) that the live backend uses, declared here to
// match the 1.4 ABI, so that the build needs neither SDK: the library is loaded at run time
// (k4a_library.h). The fake library of the tests defines the same functions from this header.
#include <cstddef>
#include <cstdint>

extern "C" {

typedef struct _k4a_device_t { size_t _rsvd; } *k4a_device_t;
typedef struct _k4a_capture_t { size_t _rsvd; } *k4a_capture_t;
typedef struct _k4a_image_t { size_t _rsvd; } *k4a_image_t;

typedef enum { K4A_RESULT_SUCCEEDED = 0, K4A_RESULT_FAILED } k4a_result_t;
typedef enum { K4A_BUFFER_RESULT_SUCCEEDED = 0, K4A_BUFFER_RESULT_FAILED, K4A_BUFFER_RESULT_TOO_SMALL } k4a_buffer_result_t;
typedef enum { K4A_WAIT_RESULT_SUCCEEDED = 0, K4A_WAIT_RESULT_FAILED, K4A_WAIT_RESULT_TIMEOUT } k4a_wait_result_t;

typedef enum {
  K4A_DEPTH_MODE_OFF = 0,
  K4A_DEPTH_MODE_NFOV_2X2BINNED,
  K4A_DEPTH_MODE_NFOV_UNBINNED,
  K4A_DEPTH_MODE_WFOV_2X2BINNED,
  K4A_DEPTH_MODE_WFOV_UNBINNED,
  K4A_DEPTH_MODE_PASSIVE_IR,
} k4a_depth_mode_t;

typedef enum {
  K4A_COLOR_RESOLUTION_OFF = 0,
  K4A_COLOR_RESOLUTION_720P,
  K4A_COLOR_RESOLUTION_1080P,
  K4A_COLOR_RESOLUTION_1440P,
  K4A_COLOR_RESOLUTION_1536P,
  K4A_COLOR_RESOLUTION_2160P,
  K4A_COLOR_RESOLUTION_3072P,
} k4a_color_resolution_t;

typedef enum {
  K4A_IMAGE_FORMAT_COLOR_MJPG = 0,
  K4A_IMAGE_FORMAT_COLOR_NV12,
  K4A_IMAGE_FORMAT_COLOR_YUY2,
  K4A_IMAGE_FORMAT_COLOR_BGRA32,
  K4A_IMAGE_FORMAT_DEPTH16,
  K4A_IMAGE_FORMAT_IR16,
  K4A_IMAGE_FORMAT_CUSTOM8,
  K4A_IMAGE_FORMAT_CUSTOM16,
  K4A_IMAGE_FORMAT_CUSTOM,
} k4a_image_format_t;

typedef enum { K4A_FRAMES_PER_SECOND_5 = 0, K4A_FRAMES_PER_SECOND_15, K4A_FRAMES_PER_SECOND_30 } k4a_fps_t;

typedef enum {
  K4A_WIRED_SYNC_MODE_STANDALONE = 0,
  K4A_WIRED_SYNC_MODE_MASTER,
  K4A_WIRED_SYNC_MODE_SUBORDINATE,
} k4a_wired_sync_mode_t;

typedef struct _k4a_device_configuration_t {
  k4a_image_format_t color_format;
  k4a_color_resolution_t color_resolution;
  k4a_depth_mode_t depth_mode;
  k4a_fps_t camera_fps;
  bool synchronized_images_only;
  int32_t depth_delay_off_color_usec;
  k4a_wired_sync_mode_t wired_sync_mode;
  uint32_t subordinate_delay_off_master_usec;
  bool disable_streaming_indicator;
} k4a_device_configuration_t;

}  // extern "C"

namespace rt::camera::k4a {

// The functions, as their pointers; the names (without the _fn) are the library's symbols.
using k4a_device_get_installed_count_fn = uint32_t (*)();
using k4a_device_open_fn = k4a_result_t (*)(uint32_t index, k4a_device_t* device);
using k4a_device_get_serialnum_fn = k4a_buffer_result_t (*)(k4a_device_t, char* serial, size_t* size);
using k4a_device_get_raw_calibration_fn = k4a_buffer_result_t (*)(k4a_device_t, uint8_t* data, size_t* size);
using k4a_device_start_cameras_fn = k4a_result_t (*)(k4a_device_t, const k4a_device_configuration_t*);
using k4a_device_get_capture_fn = k4a_wait_result_t (*)(k4a_device_t, k4a_capture_t*, int32_t timeout_ms);
using k4a_capture_get_image_fn = k4a_image_t (*)(k4a_capture_t);
using k4a_image_get_buffer_fn = uint8_t* (*)(k4a_image_t);
using k4a_image_get_size_fn = size_t (*)(k4a_image_t);
using k4a_image_get_int_fn = int (*)(k4a_image_t);
using k4a_image_get_device_timestamp_usec_fn = uint64_t (*)(k4a_image_t);
using k4a_image_get_format_fn = k4a_image_format_t (*)(k4a_image_t);
using k4a_image_release_fn = void (*)(k4a_image_t);
using k4a_capture_release_fn = void (*)(k4a_capture_t);
using k4a_device_fn = void (*)(k4a_device_t);

}  // namespace rt::camera::k4a
