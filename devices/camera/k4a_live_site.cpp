#include "camera/k4a_live_site.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <thread>

#include "camera/each_camera_in_parallel.h"
#include "camera/frame_sets.h"
#include "camera/site_camera_sources.h"

namespace rt::camera::k4a {

namespace {

constexpr size_t kMaxLiveReports = 5;
// Standalone devices' times start here, so that no aligned time is ever zero.
constexpr uint64_t kStandaloneOriginUs = 1'000'000;
constexpr size_t kBadCapturesInARow = 4;
constexpr size_t kSilentCallsBeforePolling = 3;

}  // namespace

struct LiveSite::Camera {
  std::optional<Capture> pending;  // a capture not yet in a set
  uint64_t pending_us = 0;         // its time on the site's clock
  std::optional<uint64_t> first_us, last_us;
  size_t silent_calls = 0;  // in a row: after a few, the camera is only polled, not waited for
  bool stopped = false;
};

void LiveSite::report(const std::string& problem) {
  if (!log_) return;
  std::lock_guard lock(report_mutex_);
  if (reported_ < kMaxLiveReports) std::fprintf(log_, "k4a live: %s\n", problem.c_str());
  if (reported_ == kMaxLiveReports) std::fprintf(log_, "k4a live: further problems are only counted\n");
  ++reported_;
}

std::vector<std::unique_ptr<LiveCamera>> open_live_cameras(const sim::SiteDescription& site,
                                                           const std::vector<LiveCameraSettings>& settings,
                                                           std::shared_ptr<const Library> library) {
  if (settings.size() != site.cameras.size() || settings.empty())
    throw LiveError("a live site needs one device per camera: " + std::to_string(site.cameras.size()) + " cameras, " +
                    std::to_string(settings.size()) + " devices");
  size_t masters = 0;
  for (size_t k = 0; k < settings.size(); ++k) {
    if (settings[k].fps != settings.front().fps)
      throw LiveError("camera '" + site.cameras[k].name + "' runs at " + std::to_string(settings[k].fps) + " fps, '" +
                      site.cameras.front().name + "' at " + std::to_string(settings.front().fps) +
                      ": a site's cameras run at one rate");
    if (settings[k].wired_sync == WiredSyncMode::master) ++masters;
    for (size_t j = 0; j < k; ++j)
      if (settings[j].serial == settings[k].serial)
        throw LiveError("cameras '" + site.cameras[j].name + "' and '" + site.cameras[k].name + "' name one device, '" +
                        settings[k].serial + "'");
  }
  const bool subordinates = std::any_of(settings.begin(), settings.end(), [](const LiveCameraSettings& s) {
    return s.wired_sync == WiredSyncMode::subordinate;
  });
  if (masters > 1) throw LiveError("the site file names " + std::to_string(masters) + " wired-sync masters; a site has one");
  if (subordinates && masters == 0)
    throw LiveError("the site file has wired-sync subordinates but no master: name one device \"MASTER\"");
  if (!library) library = load_k4a_library();
  std::vector<std::unique_ptr<LiveCamera>> cameras;
  for (const LiveCameraSettings& one : settings) cameras.push_back(std::make_unique<LiveCamera>(library, one));
  return cameras;
}

void start_live_cameras(const std::vector<std::unique_ptr<LiveCamera>>& cameras) {
  for (const auto& camera : cameras)
    if (camera->info().wired_sync != WiredSyncMode::master) camera->start();
  for (const auto& camera : cameras)
    if (camera->info().wired_sync == WiredSyncMode::master) camera->start();
}

LiveSite::LiveSite(const sim::SiteDescription& site, const std::vector<LiveCameraSettings>& settings, std::FILE* log,
                   std::shared_ptr<const Library> library)
    : site_(site), log_(log), decode_threads_(std::max(1u, std::thread::hardware_concurrency())) {
  devices_ = open_live_cameras(site_, settings, std::move(library));
  standalone_ = std::none_of(settings.begin(), settings.end(), [](const LiveCameraSettings& s) {
    return s.wired_sync == WiredSyncMode::master;
  });
  period_us_ = frame_period_ns(settings.front().fps) / 1000;
  for (size_t k = 0; k < devices_.size(); ++k) {
    const RecordingInfo& info = devices_[k]->info();
    const CameraIntrinsics color_lens = color_lens_for(site.cameras[k], info.color, "site file");
    site_.cameras[k].color = color_lens;
    site_.cameras[k].depth = info.depth;
    intrinsics_.push_back({color_lens, info.depth, info.color_from_depth()});
    infos_.push_back(info);
    cameras_.push_back(std::make_unique<Camera>());
  }
  start_live_cameras(devices_);
}

LiveSite::~LiveSite() = default;

// Camera k's next good capture into its pending slot, unless it has one or has stopped. Bad
// captures are skipped, a few in a row at most, so that a camera giving only bad ones sits out
// sets instead of holding the others back.
void LiveSite::fill(size_t k, int32_t wait_ms) {
  Camera& camera = *cameras_[k];
  for (size_t attempt = 0; attempt < kBadCapturesInARow && !camera.pending && !camera.stopped; ++attempt) {
    LiveCamera::Result result;
    try {
      result = devices_[k]->next_capture(camera.silent_calls >= kSilentCallsBeforePolling ? 0 : wait_ms);
    } catch (const LiveError& error) {
      camera.stopped = true;
      report(std::string(error.what()) + ": camera '" + site_.cameras[k].name + "' sits out from here");
      return;
    }
    if (result.timed_out) {
      ++camera.silent_calls;
      return;
    }
    camera.silent_calls = 0;
    if (!result.problem.empty() || !result.capture) {
      ++skipped_;
      report((result.problem.empty() ? "an empty capture" : result.problem) + ": camera '" + site_.cameras[k].name +
             "' left it out");
      continue;
    }
    const RecordingInfo& info = infos_[k];
    uint64_t time = *result.capture->color_device_us;
    if (info.wired_sync == WiredSyncMode::subordinate) time -= std::min(time, info.subordinate_delay_ns / 1000);
    if (standalone_) {
      if (!camera.first_us) camera.first_us = time;
      time = time - std::min(time, *camera.first_us) + kStandaloneOriginUs;
    }
    if (camera.last_us && time <= *camera.last_us) {
      ++skipped_;
      report("camera '" + site_.cameras[k].name + "': the capture at device time " +
             std::to_string(*result.capture->color_device_us) + " us is not after the one before it: left out");
      continue;
    }
    camera.last_us = time;
    camera.pending = std::move(result.capture);
    camera.pending_us = time;
  }
}

std::optional<sim::RgbdFrame> LiveSite::next_frame() {
  const size_t count = cameras_.size();
  // Before the first set the devices may still be starting; after it, each has its frame period.
  const int32_t wait_ms = next_index_ == 0 ? timeout_ms_ : int32_t(2 * period_us_ / 1000 + 1);
  const auto asked = std::chrono::steady_clock::now();
  std::vector<std::vector<uint64_t>> times(count);
  for (;;) {
    for_each_camera_in_parallel(count, decode_threads_, [&](size_t k) { fill(k, wait_ms); });
    bool any = false;
    for (size_t k = 0; k < count; ++k)
      if (cameras_[k]->pending) times[k] = {cameras_[k]->pending_us}, any = true;
    if (any) break;
    if (std::all_of(cameras_.begin(), cameras_.end(), [](const auto& camera) { return camera->stopped; }))
      return std::nullopt;
    if (std::chrono::steady_clock::now() - asked >= std::chrono::milliseconds(timeout_ms_))
      throw LiveError("no camera gave a capture in " + std::to_string(timeout_ms_) +
                      " ms: check that each is powered and on USB 3, and that wired-sync cables run from the master's "
                      "\"sync out\" to each subordinate's \"sync in\"");
  }
  // The earliest set of what each camera has given; a later capture waits for the next call.
  const FrameSet set = assemble_frame_sets(times, period_us_).front();
  sim::RgbdFrame frame;
  frame.index = next_index_++;
  frame.timestamp_us = set.time_us;
  frame.cameras.resize(count);
  for (size_t k = 0; k < count; ++k) {
    sim::RgbdImage& image = frame.cameras[k];
    image.camera = site_.cameras[k].name;
    image.timestamp_us = set.time_us;
    Camera& camera = *cameras_[k];
    if (set.captures[k]) {
      image.color = std::move(camera.pending->color);
      image.depth_mm = std::move(camera.pending->depth_mm);
      image.timestamp_us = camera.pending_us;
      camera.pending.reset();
    } else {
      // No surface from this camera in this set: the others render the user.
      image.color = HostImage(intrinsics_[k].color.width, intrinsics_[k].color.height, PixelFormat::RGBA8);
      image.depth_mm = HostImage(intrinsics_[k].depth.width, intrinsics_[k].depth.height, PixelFormat::R16U);
    }
  }
  return frame;
}

}  // namespace rt::camera::k4a
