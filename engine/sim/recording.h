#pragma once
// The recording format (README "Recorded sequences"): a folder with
//   calibration.json            the site description (cameras, tracker, screen) plus "format";
//                               intrinsics at the recorded images' size, or "recorded_scale"
//   frames.jsonl                one line per frame: index, nominal time, each camera's time
//   cam<K>/color_<NNNNNN>.png   8-bit RGBA, K = the camera's index in calibration.json
//   cam<K>/depth_<NNNNNN>.png   16-bit millimetres, 0 = invalid
//   tracker.jsonl               one Leap v6 tracker frame per line
//   gt/...                      ground truth (see RecordingWriter::write_ground_truth)
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "sim/recorded_rgbd_source.h"
#include "sim/site_description.h"

namespace rt::sim {

inline constexpr const char* kRecordingFormat = "remotetouch-recording/1";

std::filesystem::path color_path(const std::filesystem::path& dir, size_t camera, uint64_t frame);
std::filesystem::path depth_path(const std::filesystem::path& dir, size_t camera, uint64_t frame);
// gt/target_color_<NNNNNN>.png: the target view's RGBA as written by write_ground_truth.
std::filesystem::path ground_truth_color_path(const std::filesystem::path& dir, uint64_t frame);

// Ground truth of a frame under `dir`/gt: the target view's RGBA, depth (16-bit mm) and hand
// mask, and each camera's foreground mask (8-bit, 255 = the user).
void write_ground_truth(const std::filesystem::path& dir, uint64_t frame, const HostImage& target_rgba,
                        const HostImage& target_depth_m, const HostImage& target_part,
                        const std::vector<HostImage>& camera_parts);

class RecordingWriter {
 public:
  // `calibration` is the site description's JSON; the format tag is added to it.
  RecordingWriter(const std::filesystem::path& dir, nlohmann::json calibration);
  void write_frame(const RgbdFrame& frame);
  // sim::write_ground_truth into this recording's folder.
  void write_ground_truth(uint64_t frame, const HostImage& target_rgba, const HostImage& target_depth_m,
                          const HostImage& target_part, const std::vector<HostImage>& camera_parts) {
    sim::write_ground_truth(dir_, frame, target_rgba, target_depth_m, target_part, camera_parts);
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> camera_names_;
  std::ofstream frames_;
};

// Replays a recording, reproducing exactly the images and times that were written.
class ReplayRgbdSource : public RecordedRgbdSource {
 public:
  // Reads calibration.json (the site, and the images' sizes: its intrinsics, or those at its
  // "recorded_scale") and frames.jsonl; throws naming the file, line and field.
  explicit ReplayRgbdSource(const std::filesystem::path& dir);
  // Each image's PNG header is checked against the recorded size and kind before it is decoded.
  std::optional<RgbdFrame> next_frame() override;
  const nlohmann::json& calibration() const { return calibration_; }
  const SiteDescription& site() const override { return site_; }  // as calibrated
  const std::vector<RecordedIntrinsics>& recorded_intrinsics() const override { return recorded_; }
  size_t frame_count() const override { return frames_.size(); }
  // Of the i-th line of frames.jsonl.
  uint64_t frame_index(size_t i) const override { return frames_.at(i)["frame"].get<uint64_t>(); }
  uint64_t frame_timestamp_us(size_t i) const override { return frames_.at(i)["timestamp_us"].get<uint64_t>(); }
  void seek(size_t i) override;

 private:
  std::filesystem::path dir_;
  nlohmann::json calibration_;
  SiteDescription site_;
  std::vector<RecordedIntrinsics> recorded_;
  std::vector<std::string> camera_names_;
  std::vector<nlohmann::json> frames_;
  size_t next_ = 0;
};

}  // namespace rt::sim
