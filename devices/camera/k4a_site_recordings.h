#pragma once
// A site's cameras played from k4a recordings (Azure Kinect, Orbbec Femto): `site.json` (where
// the cameras stand, as `calibrate extrinsics` or the simulator wrote it) beside one
// `<camera name>.mkv` per camera, as `simulate --format k4a` writes a site and as each device
// records. The recordings play together aligned by device time (a subordinate's delay taken
// off), grouped into frame sets (frame_sets.h). The intrinsics are each device's factory
// calibration at its recorded modes; where a device's colour camera is apart from its depth
// camera, the depth is registered into colour on the GPU before the image-based model sees it
// (pipeline/recorded_depth_registration.h).
//
// Real data is uneven: a capture that lacks its colour or depth, or whose images cannot be
// decoded, leaves its camera out of that set (an image with no surface, which the image-based
// model ignores); each is counted and the first few are reported naming the file and time.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "camera/frame_sets.h"
#include "camera/k4a_recording_reader.h"
#include "sim/recorded_rgbd_source.h"

namespace rt::camera::k4a {

// Whether `dir` holds a site of k4a recordings (a site.json and no RemoteTouch calibration.json).
bool is_site_of_recordings(const std::filesystem::path& dir);

class SiteRecordings : public sim::RecordedRgbdSource {
 public:
  // Opens every camera's recording and indexes its captures (demuxed, not decoded). Throws
  // RecordingError or config::JsonError naming the file and what is missing or wrong. `log`
  // (may be null) gets one line per problem found, up to a few. `max_cameras` > 0 plays only
  // the first ones (a benchmark's choice).
  explicit SiteRecordings(const std::filesystem::path& dir, std::FILE* log = stderr, size_t max_cameras = 0);
  ~SiteRecordings() override;

  const sim::SiteDescription& site() const override { return site_; }
  const std::vector<RecordedIntrinsics>& recorded_intrinsics() const override { return recorded_; }
  size_t frame_count() const override { return sets_.size(); }
  uint64_t frame_index(size_t i) const override { return i; }
  uint64_t frame_timestamp_us(size_t i) const override { return sets_.at(i).time_us; }
  void seek(size_t i) override;
  // The cameras' captures are decoded side by side, on up to decode_threads() threads.
  std::optional<sim::RgbdFrame> next_frame() override;
  unsigned decode_threads() const { return decode_threads_; }
  void set_decode_threads(unsigned threads) { decode_threads_ = std::max(1u, threads); }
  // Camera k's reader's decoding time since it was last opened.
  const DecodeTimes& decode_times(size_t k) const;

  const std::vector<RecordingInfo>& infos() const { return infos_; }
  // Captures left out of every set: incomplete (colour or depth missing), out of time order, or
  // not decodable. Each camera's count of missing sets is frame_count() minus its captures.
  size_t skipped_captures() const { return skipped_; }
  // How the cameras' clocks were put together, for a person ("device time", or why not).
  const std::string& clock_description() const { return clock_; }

 private:
  struct Camera;
  void report(const std::string& problem);
  void open_reader(Camera& camera);
  // Camera k's image of the current set; empty images when it has none. A capture that cannot
  // be decoded gives its problem instead.
  sim::RgbdImage read_camera(size_t k, const FrameSet& set, std::string& problem);

  std::filesystem::path dir_;
  std::FILE* log_;
  sim::SiteDescription site_;
  std::vector<RecordedIntrinsics> recorded_;
  std::vector<RecordingInfo> infos_;
  std::vector<std::unique_ptr<Camera>> cameras_;
  std::vector<FrameSet> sets_;
  size_t next_ = 0;
  size_t skipped_ = 0;
  size_t reported_ = 0;
  unsigned decode_threads_ = 1;
  std::string clock_;
};

}  // namespace rt::camera::k4a
