#pragma once
// The input side of one site (site_runner.h), whatever its devices are: the RGBD frames and the
// tracked hands on the scene clock, from the simulator or from a recording (`site --replay`).
// A recording is RemoteTouch's format (sim/recording.h) or a real site's k4a recordings
// (camera/recorded_site.h).
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "ibr/camera_selection.h"
#include "image/host_image.h"
#include "passes/common/ibr_scene.h"
#include "sim/hand_tracker.h"
#include "sim/recorded_rgbd_source.h"
#include "sim/site_description.h"
#include "tracking/hand_skeleton.h"

namespace rt::site {

// Recorded frame times on the scene clock: frame i is due `(t_i - t_0)` after the first, in
// scene seconds (the scene clock already runs at --time-scale).
class ReplayPacing {
 public:
  // Throws std::invalid_argument when empty or when a time goes backwards.
  explicit ReplayPacing(std::vector<uint64_t> timestamps_us);
  size_t size() const { return offsets_s_.size(); }
  double time_s(size_t i) const { return offsets_s_.at(i); }
  // The newest frame due at scene time `t_s` (stale ones are skipped); empty before the first.
  std::optional<size_t> due_at(double t_s) const;
  // The mean frame rate (the scene's when there is one frame), and the playing time: up to the
  // last frame plus one frame period.
  double fps(double fallback_fps) const;
  double duration_s(double fallback_fps) const { return offsets_s_.back() + 1.0 / fps(fallback_fps); }

 private:
  std::vector<double> offsets_s_;
};

// The image-based model's cameras of a real site's devices (recorded or live): where each stands
// from the site file, its lenses as the device reports them at its modes.
std::vector<passes::IbrCameraModel> device_camera_models(const sim::SiteDescription& site,
                                                         const std::vector<sim::RecordedRgbdSource::RecordedIntrinsics>& lenses);

// A recording opened for replay at a site, checked before the site connects: its calibration is a
// valid site description, every frame's images exist, the first frame's images are readable and
// fit the calibration. Errors name the file.
class SiteReplay {
 public:
  // `max_frames`: play at most this many (0 = all).
  SiteReplay(const std::filesystem::path& dir, size_t max_frames, size_t cameras_needed);

  const std::filesystem::path& dir() const { return dir_; }
  const sim::SiteDescription& site() const { return site_; }
  // Color and depth cameras with the intrinsics of the recorded images.
  const std::vector<passes::IbrCameraModel>& cameras() const { return cameras_; }
  // Each camera's recorded intrinsics and colour-from-depth (a real device's lenses are apart).
  const std::vector<sim::RecordedRgbdSource::RecordedIntrinsics>& recorded() const { return source_->recorded_intrinsics(); }
  const ReplayPacing& pacing() const { return pacing_; }
  size_t frame_count() const { return pacing_.size(); }
  // The recorded timestamp of the first frame: the origin of the tracker's times too.
  uint64_t origin_us() const { return origin_us_; }
  // Reads the i-th frame; throws naming an unreadable image or one of another size.
  sim::RgbdFrame read(size_t i);
  // The recorded ground truth of the i-th frame (gt/target_color), when there is one.
  std::optional<HostImage> ground_truth(size_t i) const;
  // Whether the folder holds the hand tracker's recording, tracker.jsonl. The vendor's recorder
  // and `record` write none: such a replay sends no tracked hands.
  bool has_tracker() const { return has_tracker_; }
  // tracker.jsonl, as a device; one that gives no frames where there is none.
  std::unique_ptr<sim::HandTracker> tracker() const;

 private:
  std::filesystem::path dir_;
  std::unique_ptr<sim::RecordedRgbdSource> source_;
  sim::SiteDescription site_;
  std::vector<passes::IbrCameraModel> cameras_;
  ReplayPacing pacing_;
  uint64_t origin_us_ = 0;
  bool has_tracker_ = false;
};

// A hand tracker paced on the scene clock: the newest frame due, in site-frame skeletons
// (sim::skeletons_in_site, through the site's tracker placement). Not thread-safe.
class PacedHandTracker {
 public:
  // Frame times are taken relative to `origin_us` (the recording's first RGBD frame; 0 for the
  // simulated tracker, which starts at scene time 0).
  PacedHandTracker(std::unique_ptr<sim::HandTracker> tracker, const sim::TrackerPlacement& placement, uint64_t origin_us);
  struct Hands {
    double time_s = 0;  // scene time of the tracker frame
    std::vector<HandSkeleton> hands;
  };
  // The frame due at scene time `t_s`; the last one stands after the device's end (a real user
  // does not vanish when the recording stops). Empty before the first frame.
  std::optional<Hands> at(double t_s);

 private:
  std::unique_ptr<sim::HandTracker> tracker_;
  sim::TrackerPlacement placement_;
  uint64_t origin_us_;
  std::optional<sim::TrackerFrame> pending_;  // read ahead, not due yet
  std::optional<Hands> current_;
  bool ended_ = false;
};

// The tracked hands of the last two seconds by scene time, for the image-based model's camera
// choice: the tracker is what a real site knows of its user's hands. Thread-safe.
class TrackedHandsHistory {
 public:
  void add(double time_s, std::vector<HandSkeleton> hands);
  // The entry closest in time; empty when there is none yet.
  std::optional<std::vector<HandSkeleton>> closest(double time_s) const;

 private:
  mutable std::mutex mutex_;
  std::deque<std::pair<double, std::vector<HandSkeleton>>> entries_;
};

// The hand reaching for the glass among the tracked ones: of two, the nearer the screen
// (ibr::touching_hand); of one, that one; of none, the right (the paper's default side).
ibr::TouchingHand touching_side(const std::vector<HandSkeleton>& hands);

}  // namespace rt::site
