#pragma once
// Writes one camera's captures as a k4a recording (the Matroska file k4arecorder and Orbbec's
// K4A wrapper write), so that the SDK's playback and our reader take it as a real camera's:
// COLOR and DEPTH tracks of codec V_MS/VFW/FOURCC with a 40-byte BITMAPINFOHEADER, a
// DefaultDuration of the frame period, the K4A_* tags and the factory calibration attached as
// calibration.json. Block timecodes are microseconds from the first capture; device time =
// timecode + K4A_START_OFFSET_NS / 1000.
//
// libebml / libmatroska write the file, as the SDK does: FFmpeg's muxer names MJPG V_MJPEG and
// will not store big-endian 16-bit depth under its FourCC.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "camera/k4a_calibration.h"
#include "camera/k4a_modes.h"
#include "image/host_image.h"

namespace rt::camera::k4a {

enum class WiredSyncMode { standalone, master, subordinate };
std::string_view wired_sync_mode_name(WiredSyncMode mode);  // the tag value: "STANDALONE", ...

struct RecordingConfig {
  ColorFormat color_format = ColorFormat::mjpg;
  ColorResolution color_resolution = ColorResolution::p720;
  DepthMode depth_mode = DepthMode::nfov_unbinned;
  uint32_t fps = 30;           // 5, 15 or 30
  int64_t depth_delay_ns = 0;  // depth capture time minus colour capture time
  WiredSyncMode wired_sync = WiredSyncMode::standalone;
  uint64_t subordinate_delay_ns = 0;  // only written for a subordinate
  std::string serial;                 // K4A_DEVICE_SERIAL_NUMBER; written when not empty
  DeviceCalibration calibration;
};

// Colour images as the tracks store them: JPEG at `quality` (1..100) for MJPG, bytes B, G, R, A
// for BGRA. `rgba` is RGBA8 (HostImage keeps 8-bit texels as floats in [0, 1]).
std::vector<uint8_t> encode_mjpg(const HostImage& rgba, int quality);
std::vector<uint8_t> encode_bgra(const HostImage& rgba);

class RecordingWriter {
 public:
  // Creates the file; throws std::runtime_error naming the path when it cannot, and
  // std::invalid_argument for a frame rate that is not a k4a one.
  RecordingWriter(const std::filesystem::path& path, RecordingConfig config);
  ~RecordingWriter();  // closes the file if close() was not called (errors then are lost)
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  // One capture: the colour track's bytes at the colour camera's device time (encode_mjpg or
  // encode_bgra; NV12 and YUY2 frames of the mode's size as the device gives them), and depth in
  // millimetres (R16U, the mode's size) at that time plus the depth delay. A camera that dropped
  // one of the two gives no colour bytes, or a 0x0 depth image. Device times must increase from
  // capture to capture. Throws std::invalid_argument for images of the wrong size.
  void write_capture(uint64_t color_device_time_us, std::span<const uint8_t> color, const HostImage& depth_mm);
  // Writes the index, the duration and the seek head. Throws on an I/O error.
  void close();

  const std::filesystem::path& path() const { return path_; }
  size_t captures_written() const { return captures_; }

 private:
  struct Matroska;
  void write_header(uint64_t start_offset_ns);
  std::filesystem::path path_;
  RecordingConfig config_;
  std::unique_ptr<Matroska> file_;
  size_t captures_ = 0;
  uint64_t last_time_us_ = 0;
  bool closed_ = false;
};

}  // namespace rt::camera::k4a
