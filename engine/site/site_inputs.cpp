#include "site/site_inputs.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "camera/k4a_site_recordings.h"
#include "camera/recorded_site.h"
#include "pipeline/site_simulator.h"
#include "config/json.h"
#include "image/image_io.h"
#include "sim/recording.h"
#include "sim/tracker_replay.h"
#include "sim/tracker_space.h"

namespace rt::site {

ReplayPacing::ReplayPacing(std::vector<uint64_t> timestamps_us) {
  if (timestamps_us.empty()) throw std::invalid_argument("a replay needs at least one frame");
  for (size_t i = 0; i < timestamps_us.size(); ++i) {
    if (i > 0 && timestamps_us[i] < timestamps_us[i - 1])
      throw std::invalid_argument("frame " + std::to_string(i) + "'s time (" + std::to_string(timestamps_us[i]) +
                                  " us) is before the previous frame's (" + std::to_string(timestamps_us[i - 1]) + " us)");
    offsets_s_.push_back(double(timestamps_us[i] - timestamps_us[0]) * 1e-6);
  }
}

std::optional<size_t> ReplayPacing::due_at(double t_s) const {
  // The first frame later than t_s; the one before it is due.
  const auto later = std::upper_bound(offsets_s_.begin(), offsets_s_.end(), t_s);
  if (later == offsets_s_.begin()) return std::nullopt;
  return size_t(later - offsets_s_.begin()) - 1;
}

double ReplayPacing::fps(double fallback_fps) const {
  if (offsets_s_.size() < 2 || !(offsets_s_.back() > 0)) return fallback_fps;
  return double(offsets_s_.size() - 1) / offsets_s_.back();
}

namespace {

std::unique_ptr<sim::RecordedRgbdSource> open_recording(const std::filesystem::path& dir) {
  try {
    return camera::open_recorded_site(dir);
  } catch (const std::exception& error) {
    throw std::runtime_error(std::string("--replay: ") + error.what());
  }
}

}  // namespace

std::vector<passes::IbrCameraModel> device_camera_models(const sim::SiteDescription& site,
                                                         const std::vector<sim::RecordedRgbdSource::RecordedIntrinsics>& lenses) {
  std::vector<passes::IbrCameraModel> models;
  for (size_t k = 0; k < site.cameras.size(); ++k) {
    const sim::RgbdCamera& camera = site.cameras[k];
    passes::IbrCameraModel model{camera.color_camera(), camera.depth_camera()};
    model.color.intrinsics = lenses.at(k).color;
    model.depth.intrinsics = lenses.at(k).depth;
    models.push_back(model);
  }
  return models;
}

SiteReplay::SiteReplay(const std::filesystem::path& dir, size_t max_frames, size_t cameras_needed)
    : dir_(dir), source_(open_recording(dir)), pacing_(std::vector<uint64_t>{0}) {
  const bool k4a = camera::k4a::is_site_of_recordings(dir_);
  const std::string description = "'" + (dir_ / (k4a ? "site.json" : "calibration.json")).string() + "'";
  const std::string frames_file = k4a ? "the k4a recordings in '" + dir_.string() + "'" : "'" + (dir_ / "frames.jsonl").string() + "'";
  site_ = source_->site();
  if (site_.cameras.size() < cameras_needed)
    throw std::runtime_error(description + " has " + std::to_string(site_.cameras.size()) +
                             " cameras; the image-based model uses " + std::to_string(cameras_needed));
  const size_t count = max_frames ? std::min(max_frames, source_->frame_count()) : source_->frame_count();
  if (count == 0) throw std::runtime_error(frames_file + (k4a ? " hold no frames" : " lists no frames"));
  std::vector<uint64_t> times;
  for (size_t i = 0; i < count; ++i) times.push_back(source_->frame_timestamp_us(i));
  try {
    pacing_ = ReplayPacing(std::move(times));
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(frames_file + ": " + error.what());
  }
  origin_us_ = source_->frame_timestamp_us(0);
  // Every image there before the peer is kept waiting for a site that fails half way; reading
  // them all would take as long as the replay, so only the first frame is read now. (A k4a
  // recording's captures were all found when it was indexed.)
  if (!k4a)
    for (size_t i = 0; i < count; ++i)
      for (size_t k = 0; k < site_.cameras.size(); ++k)
        for (const auto& file : {sim::color_path(dir_, k, source_->frame_index(i)), sim::depth_path(dir_, k, source_->frame_index(i))})
          if (!std::filesystem::is_regular_file(file))
            throw std::runtime_error("recording '" + dir_.string() + "': frame " + std::to_string(source_->frame_index(i)) +
                                     " has no image '" + file.string() + "'");
  // The first frame read whole (each image checked against the recorded size first).
  source_->seek(0);
  source_->next_frame();
  cameras_ = device_camera_models(site_, source_->recorded_intrinsics());
  // Cameras without a tracker still make a call (the portraits, the viewer's eye): a real site's
  // recordings seldom come with one. A tracker recording that is there must be whole.
  has_tracker_ = std::filesystem::exists(dir_ / "tracker.jsonl");
  if (has_tracker_) sim::check_tracker_recording(dir_ / "tracker.jsonl");
}

sim::RgbdFrame SiteReplay::read(size_t i) {
  source_->seek(i);
  return *source_->next_frame();
}

std::optional<HostImage> SiteReplay::ground_truth(size_t i) const {
  const std::filesystem::path file = sim::ground_truth_color_path(dir_, source_->frame_index(i));
  if (!std::filesystem::is_regular_file(file)) return std::nullopt;
  return read_image(file);
}

namespace {

// A recording without a tracker: nobody's hands are seen.
class NoTrackedHands : public sim::HandTracker {
 public:
  std::optional<sim::TrackerFrame> next_frame() override { return std::nullopt; }
};

}  // namespace

std::unique_ptr<sim::HandTracker> SiteReplay::tracker() const {
  if (!has_tracker_) return std::make_unique<NoTrackedHands>();
  return std::make_unique<sim::ReplayHandTracker>(dir_ / "tracker.jsonl");
}

PacedHandTracker::PacedHandTracker(std::unique_ptr<sim::HandTracker> tracker, const sim::TrackerPlacement& placement,
                                   uint64_t origin_us)
    : tracker_(std::move(tracker)), placement_(placement), origin_us_(origin_us) {}

std::optional<PacedHandTracker::Hands> PacedHandTracker::at(double t_s) {
  auto time_of = [&](const sim::TrackerFrame& frame) { return (double(frame.timestamp_us) - double(origin_us_)) * 1e-6; };
  while (!ended_) {
    if (!pending_) {
      pending_ = tracker_->next_frame();
      if (!pending_) {
        ended_ = true;
        break;
      }
    }
    if (time_of(*pending_) > t_s) break;
    current_ = Hands{time_of(*pending_), sim::skeletons_in_site(*pending_, placement_)};
    pending_.reset();
  }
  return current_;
}

void TrackedHandsHistory::add(double time_s, std::vector<HandSkeleton> hands) {
  std::lock_guard lock(mutex_);
  entries_.emplace_back(time_s, std::move(hands));
  while (entries_.size() > 1 && entries_.back().first - entries_.front().first > 2.0) entries_.pop_front();
}

std::optional<std::vector<HandSkeleton>> TrackedHandsHistory::closest(double time_s) const {
  std::lock_guard lock(mutex_);
  const std::pair<double, std::vector<HandSkeleton>>* best = nullptr;
  for (const auto& entry : entries_)
    if (!best || std::abs(entry.first - time_s) < std::abs(best->first - time_s)) best = &entry;
  if (!best) return std::nullopt;
  return best->second;
}

ibr::TouchingHand touching_side(const std::vector<HandSkeleton>& hands) {
  const HandSkeleton* nearest[2] = {nullptr, nullptr};  // right, left
  for (const HandSkeleton& hand : hands) {
    if (!hand.palm.allFinite()) continue;
    const HandSkeleton*& slot = nearest[hand.is_left ? 1 : 0];
    if (!slot || hand.palm.z() < slot->palm.z()) slot = &hand;
  }
  if (nearest[0] && nearest[1]) return ibr::touching_hand(*nearest[0], *nearest[1]);
  return nearest[1] ? ibr::TouchingHand::Left : ibr::TouchingHand::Right;
}

}  // namespace rt::site
