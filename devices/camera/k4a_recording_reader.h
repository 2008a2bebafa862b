#pragma once
// Reads a k4a recording (Azure Kinect / Orbbec Femto, one .mkv per camera) through FFmpeg's
// libraries: the recorded modes and tags, the factory calibration at those modes, and the
// captures decoded (every colour format the devices record: MJPG, NV12, YUY2, BGRA; depth
// "b16g", big-endian millimetres).
//
// Everything read is checked against the modes before it is used, so that no file makes us
// allocate beyond one capture of the largest mode: track sizes must be the mode's, a depth
// frame must be exactly its size, a JPEG may not decode to more pixels than its track has.
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "camera/k4a_calibration.h"
#include "camera/k4a_color_decoder.h"
#include "camera/k4a_modes.h"
#include "camera/k4a_recording_writer.h"
#include "image/host_image.h"

struct AVPacket;

namespace rt::camera::k4a {

// Errors start with the file's path and say what is wrong with it.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RecordingInfo {
  ColorFormat color_format = ColorFormat::mjpg;
  ColorResolution color_resolution = ColorResolution::p720;
  DepthMode depth_mode = DepthMode::nfov_unbinned;
  uint32_t fps = 30;
  WiredSyncMode wired_sync = WiredSyncMode::standalone;
  int64_t depth_delay_ns = 0;
  uint64_t subordinate_delay_ns = 0;
  uint64_t start_offset_us = 0;  // device time of timecode 0
  std::string serial;            // empty when the tag is absent
  DeviceCalibration calibration;
  CameraIntrinsics color, depth;  // at the recorded modes, OpenCV's convention
  Eigen::Isometry3d color_from_depth() const { return calibration.color_from_depth(); }
};

// One capture: the colour and depth images taken together (within half a frame period, the
// depth delay allowed for). A camera that dropped one of the two leaves it empty.
struct Capture {
  std::optional<uint64_t> color_device_us, depth_device_us;
  HostImage color;     // RGBA8; empty (0x0) without colour
  HostImage depth_mm;  // R16U, 0 = no measurement; empty without depth
};

// When a capture's images were taken, without decoding them.
struct CaptureTimes {
  std::optional<uint64_t> color_device_us, depth_device_us;
};

class RecordingReader {
 public:
  // Opens the file and checks its tracks, tags and calibration; throws RecordingError.
  explicit RecordingReader(const std::filesystem::path& path);
  ~RecordingReader();
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;

  const RecordingInfo& info() const { return info_; }
  // The next capture, decoded; empty at the end of the file. A frame that cannot be decoded
  // (corrupt JPEG, a depth frame of the wrong size, a truncated block) throws RecordingError
  // naming the file, the track and the device time.
  std::optional<Capture> next_capture();
  // The next capture's times, its images left undecoded: how a replay indexes a file and skips
  // what it has no time to show. Throws RecordingError for a truncated file, as next_capture.
  std::optional<CaptureTimes> skip_capture();
  const DecodeTimes& decode_times() const { return times_; }

 private:
  struct Demuxer;
  struct CapturePackets {
    std::shared_ptr<AVPacket> color, depth;
  };
  CapturePackets read_capture_packets();
  uint64_t device_us(const AVPacket& packet) const;
  std::filesystem::path path_;
  std::unique_ptr<Demuxer> demuxer_;
  RecordingInfo info_;
  DecodeTimes times_;
};

}  // namespace rt::camera::k4a
