#pragma once
// One live Azure Kinect DK or Orbbec Femto through the k4a C API (k4a_library.h): opened by
// serial number, started in the modes and wired-sync role the site file gives it, its captures
// decoded into the same images a recording of it gives (the recordings' colour decoder).
//
// A device's images are checked before they are read: a null buffer, a format other than the
// one started, sizes or strides that are not the mode's, a depth image of the wrong byte count.
// Such a capture is not returned; its problem is, so that the site counts it and goes on.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/k4a_color_decoder.h"
#include "camera/k4a_library.h"
#include "camera/k4a_recording_reader.h"

namespace rt::camera::k4a {

// What the site file asks of one device.
struct LiveCameraSettings {
  std::string serial;
  ColorFormat color_format = ColorFormat::mjpg;
  ColorResolution color_resolution = ColorResolution::p720;
  DepthMode depth_mode = DepthMode::nfov_unbinned;
  uint32_t fps = 30;
  WiredSyncMode wired_sync = WiredSyncMode::standalone;
  uint32_t subordinate_delay_us = 0;  // a subordinate's, off the master's
  int32_t depth_delay_us = 0;         // depth capture time minus colour capture time
};

// The serial numbers of the connected devices that could be opened, in the library's order;
// `unopened` counts those that could not (in use by another program).
std::vector<std::string> connected_serials(const Library& library, size_t* unopened = nullptr);

class LiveCamera {
 public:
  // Opens the device with settings.serial and reads its factory calibration; throws LiveError
  // listing the serials found when no device has it.
  LiveCamera(std::shared_ptr<const Library> library, const LiveCameraSettings& settings);
  ~LiveCamera();  // stops the cameras and closes the device
  LiveCamera(const LiveCamera&) = delete;
  LiveCamera& operator=(const LiveCamera&) = delete;

  // The modes, sync role and calibration at the modes, as a recording of the device states them.
  const RecordingInfo& info() const { return info_; }
  // Throws LiveError when the device refuses the modes.
  void start();
  struct Result {
    std::optional<Capture> capture;  // with both images (colour left empty when its bytes were kept)
    std::vector<uint8_t> color_bytes;  // as the device gave them, when kept instead of decoded
    std::string problem;             // why a capture that came was left out
    bool timed_out = false;
  };
  // The next capture, waiting up to `timeout_ms`. `keep_bytes`: the colour image's bytes are
  // kept as they came (what a recording stores) instead of decoded. Throws LiveError when the
  // device fails (it was unplugged, or stopped).
  Result next_capture(int32_t timeout_ms, bool keep_bytes = false);

 private:
  std::shared_ptr<const Library> library_;
  k4a_device_t device_ = nullptr;
  LiveCameraSettings settings_;
  RecordingInfo info_;
  std::unique_ptr<ColorDecoder> decoder_;
  DecodeTimes times_;
  bool started_ = false;
};

}  // namespace rt::camera::k4a
