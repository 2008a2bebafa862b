#include "camera/k4a_live_camera.h"

#include <algorithm>
#include <cstring>

namespace rt::camera::k4a {

namespace {

// A serial number is a dozen characters and a calibration a few kilobytes: a device that says
// it needs more is not believed.
constexpr size_t kMaxSerialBytes = 256;
constexpr size_t kMaxLiveCalibrationBytes = 1 << 20;
// A USB host has a few devices; a count far beyond is not believed either (each is opened to ask).
constexpr uint32_t kMaxDevices = 64;

k4a_image_format_t api_color_format(ColorFormat format) {
  switch (format) {
    case ColorFormat::mjpg: return K4A_IMAGE_FORMAT_COLOR_MJPG;
    case ColorFormat::nv12: return K4A_IMAGE_FORMAT_COLOR_NV12;
    case ColorFormat::yuy2: return K4A_IMAGE_FORMAT_COLOR_YUY2;
    case ColorFormat::bgra: return K4A_IMAGE_FORMAT_COLOR_BGRA32;
  }
  return K4A_IMAGE_FORMAT_CUSTOM;
}

k4a_color_resolution_t api_color_resolution(ColorResolution resolution) {
  switch (resolution) {
    case ColorResolution::p720: return K4A_COLOR_RESOLUTION_720P;
    case ColorResolution::p1080: return K4A_COLOR_RESOLUTION_1080P;
    case ColorResolution::p1440: return K4A_COLOR_RESOLUTION_1440P;
    case ColorResolution::p1536: return K4A_COLOR_RESOLUTION_1536P;
    case ColorResolution::p2160: return K4A_COLOR_RESOLUTION_2160P;
    case ColorResolution::p3072: return K4A_COLOR_RESOLUTION_3072P;
  }
  return K4A_COLOR_RESOLUTION_OFF;
}

k4a_depth_mode_t api_depth_mode(DepthMode mode) {
  switch (mode) {
    case DepthMode::nfov_2x2_binned: return K4A_DEPTH_MODE_NFOV_2X2BINNED;
    case DepthMode::nfov_unbinned: return K4A_DEPTH_MODE_NFOV_UNBINNED;
    case DepthMode::wfov_2x2_binned: return K4A_DEPTH_MODE_WFOV_2X2BINNED;
    case DepthMode::wfov_unbinned: return K4A_DEPTH_MODE_WFOV_UNBINNED;
  }
  return K4A_DEPTH_MODE_OFF;
}

k4a_wired_sync_mode_t api_wired_sync(WiredSyncMode mode) {
  switch (mode) {
    case WiredSyncMode::standalone: return K4A_WIRED_SYNC_MODE_STANDALONE;
    case WiredSyncMode::master: return K4A_WIRED_SYNC_MODE_MASTER;
    case WiredSyncMode::subordinate: return K4A_WIRED_SYNC_MODE_SUBORDINATE;
  }
  return K4A_WIRED_SYNC_MODE_STANDALONE;
}

// The bytes a row of a raw colour format has at width `w`; 0 for MJPG, which has no rows.
size_t color_row_bytes(ColorFormat format, uint32_t w) {
  switch (format) {
    case ColorFormat::mjpg: return 0;
    case ColorFormat::nv12: return w;
    case ColorFormat::yuy2: return size_t(w) * 2;
    case ColorFormat::bgra: return size_t(w) * 4;
  }
  return 0;
}

std::string device_serial(const Library& library, k4a_device_t device) {
  size_t size = 0;
  if (library.device_get_serialnum(device, nullptr, &size) != K4A_BUFFER_RESULT_TOO_SMALL || size == 0 ||
      size > kMaxSerialBytes)
    return "";
  std::vector<char> text(size, '\0');
  if (library.device_get_serialnum(device, text.data(), &size) != K4A_BUFFER_RESULT_SUCCEEDED) return "";
  return std::string(text.data(), strnlen(text.data(), text.size()));
}

// Releases what the library lent us, whichever way the reading ends.
struct LentCapture {
  const Library& library;
  k4a_capture_t capture = nullptr;
  k4a_image_t color = nullptr, depth = nullptr;
  ~LentCapture() {
    if (color) library.image_release(color);
    if (depth) library.image_release(depth);
    if (capture) library.capture_release(capture);
  }
};

}  // namespace

std::vector<std::string> connected_serials(const Library& library, size_t* unopened) {
  std::vector<std::string> serials;
  if (unopened) *unopened = 0;
  const uint32_t count = std::min(library.device_get_installed_count(), kMaxDevices);
  for (uint32_t i = 0; i < count; ++i) {
    k4a_device_t device = nullptr;
    if (library.device_open(i, &device) != K4A_RESULT_SUCCEEDED || !device) {
      if (unopened) ++*unopened;
      continue;
    }
    serials.push_back(device_serial(library, device));
    library.device_close(device);
  }
  return serials;
}

LiveCamera::LiveCamera(std::shared_ptr<const Library> library, const LiveCameraSettings& settings)
    : library_(std::move(library)), settings_(settings) {
  const Library& lib = *library_;
  const std::string where = "k4a device '" + settings.serial + "'";
  std::vector<std::string> found;
  size_t unopened = 0;
  const uint32_t count = std::min(lib.device_get_installed_count(), kMaxDevices);
  for (uint32_t i = 0; i < count && !device_; ++i) {
    k4a_device_t device = nullptr;
    if (lib.device_open(i, &device) != K4A_RESULT_SUCCEEDED || !device) {
      ++unopened;
      continue;
    }
    const std::string serial = device_serial(lib, device);
    if (serial == settings.serial) {
      device_ = device;
    } else {
      found.push_back(serial.empty() ? "(no serial)" : serial);
      lib.device_close(device);
    }
  }
  if (!device_) {
    std::string message = where + " is not connected: ";
    if (count == 0) {
      message += "no k4a device is connected (plug the Azure Kinect or Femto in by USB 3 and power it";
    } else {
      message += "the connected devices are";
      for (const std::string& serial : found) message += " '" + serial + "'";
      if (found.empty()) message += " none that could be opened";
      message += " (plug in the one the site file names, or correct its \"serial\"";
    }
    if (unopened > 0)
      message += "; " + std::to_string(unopened) + " could not be opened: another program (k4aviewer, a recorder) may hold it";
    throw LiveError(message + ")");
  }

  try {
    size_t size = 0;
    if (lib.device_get_raw_calibration(device_, nullptr, &size) != K4A_BUFFER_RESULT_TOO_SMALL || size == 0 ||
        size > kMaxLiveCalibrationBytes)
      throw LiveError(where + " gives no factory calibration (or one larger than 1 MiB)");
    std::vector<uint8_t> raw(size);
    if (lib.device_get_raw_calibration(device_, raw.data(), &size) != K4A_BUFFER_RESULT_SUCCEEDED || size > raw.size())
      throw LiveError(where + ": reading its factory calibration failed");
    std::string_view text(reinterpret_cast<const char*>(raw.data()), size);
    while (!text.empty() && text.back() == '\0') text.remove_suffix(1);  // the SDK counts the terminator
    info_.calibration = parse_calibration_json(text, where);
    info_.color = color_intrinsics(info_.calibration.color, settings.color_resolution);
    info_.depth = depth_intrinsics(info_.calibration.depth, settings.depth_mode);
    decoder_ = std::make_unique<ColorDecoder>(settings.color_format, settings.color_resolution);
  } catch (const CalibrationError& error) {
    lib.device_close(device_);
    throw LiveError(error.what());
  } catch (const ImageError& error) {
    lib.device_close(device_);
    throw LiveError(where + ": " + error.what());
  } catch (...) {
    lib.device_close(device_);
    throw;
  }
  info_.color_format = settings.color_format;
  info_.color_resolution = settings.color_resolution;
  info_.depth_mode = settings.depth_mode;
  info_.fps = settings.fps;
  info_.wired_sync = settings.wired_sync;
  info_.depth_delay_ns = int64_t(settings.depth_delay_us) * 1000;
  info_.subordinate_delay_ns = uint64_t(settings.subordinate_delay_us) * 1000;
  info_.serial = settings.serial;
}

LiveCamera::~LiveCamera() {
  if (started_) library_->device_stop_cameras(device_);
  library_->device_close(device_);
}

void LiveCamera::start() {
  if (started_) return;
  k4a_device_configuration_t config{};
  config.color_format = api_color_format(settings_.color_format);
  config.color_resolution = api_color_resolution(settings_.color_resolution);
  config.depth_mode = api_depth_mode(settings_.depth_mode);
  config.camera_fps = settings_.fps == 5 ? K4A_FRAMES_PER_SECOND_5 : settings_.fps == 15 ? K4A_FRAMES_PER_SECOND_15
                                                                                          : K4A_FRAMES_PER_SECOND_30;
  // A capture then always holds both images, which is what a frame set needs of a camera.
  config.synchronized_images_only = true;
  config.depth_delay_off_color_usec = settings_.depth_delay_us;
  config.wired_sync_mode = api_wired_sync(settings_.wired_sync);
  config.subordinate_delay_off_master_usec =
      settings_.wired_sync == WiredSyncMode::subordinate ? settings_.subordinate_delay_us : 0;
  config.disable_streaming_indicator = false;
  if (library_->device_start_cameras(device_, &config) != K4A_RESULT_SUCCEEDED)
    throw LiveError("k4a device '" + settings_.serial + "' refused to start in " +
                    color_mode_tag(settings_.color_format, settings_.color_resolution) + ", " +
                    std::string(depth_mode_name(settings_.depth_mode)) + " at " + std::to_string(settings_.fps) + " fps, " +
                    std::string(wired_sync_mode_name(settings_.wired_sync)) +
                    " (3072P and WFOV_UNBINNED run at 15 fps at most; a subordinate needs the sync cable from its master)");
  started_ = true;
}

LiveCamera::Result LiveCamera::next_capture(int32_t timeout_ms, bool keep_bytes) {
  const Library& lib = *library_;
  const std::string where = "k4a device '" + settings_.serial + "'";
  Result result;
  LentCapture lent{lib};
  switch (lib.device_get_capture(device_, &lent.capture, timeout_ms)) {
    case K4A_WAIT_RESULT_SUCCEEDED: break;
    case K4A_WAIT_RESULT_TIMEOUT: result.timed_out = true; return result;
    default:
      throw LiveError(where + " stopped giving captures (unplugged, its USB connection failed, or its cameras are not started)");
  }
  if (!lent.capture) {
    result.problem = where + " gave an empty capture";
    return result;
  }
  lent.color = lib.capture_get_color_image(lent.capture);
  lent.depth = lib.capture_get_depth_image(lent.capture);
  if (!lent.color || !lent.depth) {
    result.problem = where + ": a capture without its " + std::string(lent.color ? "depth" : "colour") + " image";
    return result;
  }
  const uint64_t color_us = lib.image_get_device_timestamp_usec(lent.color);
  const uint64_t depth_us = lib.image_get_device_timestamp_usec(lent.depth);
  const std::string color_name = where + ": colour image at device time " + std::to_string(color_us) + " us";
  const std::string depth_name = where + ": depth image at device time " + std::to_string(depth_us) + " us";

  // Every number the device gives is checked against the mode before a byte is read.
  const SensorCut& color_cut = sensor_cut(settings_.color_resolution);
  const SensorCut& depth_cut = sensor_cut(settings_.depth_mode);
  const auto size_text = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
  const int cw = lib.image_get_width_pixels(lent.color), ch = lib.image_get_height_pixels(lent.color);
  const int dw = lib.image_get_width_pixels(lent.depth), dh = lib.image_get_height_pixels(lent.depth);
  const uint8_t* color_bytes = lib.image_get_buffer(lent.color);
  const uint8_t* depth_bytes = lib.image_get_buffer(lent.depth);
  const size_t color_size = lib.image_get_size(lent.color), depth_size = lib.image_get_size(lent.depth);
  const size_t color_row = color_row_bytes(settings_.color_format, color_cut.output_width);
  const size_t depth_row = size_t(depth_cut.output_width) * 2;
  if (lib.image_get_format(lent.color) != api_color_format(settings_.color_format))
    result.problem = color_name + " is in format " + std::to_string(int(lib.image_get_format(lent.color))) + ", not " +
                     std::string(color_format_name(settings_.color_format)) + " as started";
  else if (uint32_t(cw) != color_cut.output_width || uint32_t(ch) != color_cut.output_height)
    result.problem = color_name + " is " + size_text(cw, ch) + ", the mode is " +
                     size_text(int(color_cut.output_width), int(color_cut.output_height));
  else if (color_row != 0 && size_t(lib.image_get_stride_bytes(lent.color)) != color_row)
    result.problem = color_name + " has rows of " + std::to_string(lib.image_get_stride_bytes(lent.color)) +
                     " bytes, the mode's are " + std::to_string(color_row);
  else if (!color_bytes)
    result.problem = color_name + " has no buffer";
  else if (lib.image_get_format(lent.depth) != K4A_IMAGE_FORMAT_DEPTH16)
    result.problem = depth_name + " is in format " + std::to_string(int(lib.image_get_format(lent.depth))) + ", not DEPTH16";
  else if (uint32_t(dw) != depth_cut.output_width || uint32_t(dh) != depth_cut.output_height)
    result.problem = depth_name + " is " + size_text(dw, dh) + ", the mode is " +
                     size_text(int(depth_cut.output_width), int(depth_cut.output_height));
  else if (size_t(lib.image_get_stride_bytes(lent.depth)) != depth_row || depth_size != depth_row * depth_cut.output_height)
    result.problem = depth_name + " has " + std::to_string(depth_size) + " bytes in rows of " +
                     std::to_string(lib.image_get_stride_bytes(lent.depth)) + ", the mode needs " +
                     std::to_string(depth_row * depth_cut.output_height) + " in rows of " + std::to_string(depth_row);
  else if (!depth_bytes)
    result.problem = depth_name + " has no buffer";
  if (!result.problem.empty()) return result;

  Capture capture;
  capture.color_device_us = color_us;
  capture.depth_device_us = depth_us;
  if (keep_bytes) {
    result.problem = color_size_problem(settings_.color_format, settings_.color_resolution, color_size, color_name);
    if (!result.problem.empty()) return result;
    result.color_bytes.assign(color_bytes, color_bytes + color_size);
  } else {
    try {
      capture.color = decoder_->decode(color_bytes, color_size, color_name, times_);
    } catch (const ImageError& error) {
      result.problem = error.what();
      return result;
    }
  }
  // DEPTH16 is millimetres in the machine's (little-endian) order; a recording stores them swapped.
  capture.depth_mm = HostImage(depth_cut.output_width, depth_cut.output_height, PixelFormat::R16U);
  for (size_t i = 0; i < capture.depth_mm.texels.size(); ++i) {
    uint16_t value;
    std::memcpy(&value, depth_bytes + 2 * i, 2);
    capture.depth_mm.texels[i] = float(value);
  }
  result.capture = std::move(capture);
  return result;
}

}  // namespace rt::camera::k4a
