#include "camera/k4a_live_recorder.h"

#include <algorithm>
#include <chrono>

#include "camera/k4a_live_site.h"
#include "camera/k4a_recording_writer.h"
#include "camera/k4a_site_writer.h"
#include "camera/site_camera_sources.h"
#include "time/monotonic_clock.h"

namespace rt::camera::k4a {

namespace {

constexpr size_t kMaxRecordReports = 5;
constexpr int32_t kRecordTimeoutMs = 2000;

}  // namespace

RecordSummary record_live_site(const sim::SiteDescription& site, const std::string& site_where,
                               const std::filesystem::path& out, double seconds, std::FILE* log,
                               std::shared_ptr<const Library> library) {
  if (!(seconds > 0)) throw LiveError("record: the time to record must be more than 0 s");
  std::error_code error;
  if (std::filesystem::exists(out / "site.json", error))
    throw LiveError("'" + out.string() + "' holds a site already (site.json): record into a new folder");
  const std::vector<LiveCameraSettings> settings = live_site_settings(site, site_where);
  std::vector<std::unique_ptr<LiveCamera>> cameras = open_live_cameras(site, settings, std::move(library));

  std::filesystem::create_directories(out);
  std::vector<std::unique_ptr<RecordingWriter>> writers;
  sim::SiteDescription recorded = site;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const RecordingInfo& info = cameras[k]->info();
    RecordingConfig config;
    config.color_format = info.color_format;
    config.color_resolution = info.color_resolution;
    config.depth_mode = info.depth_mode;
    config.fps = info.fps;
    config.depth_delay_ns = info.depth_delay_ns;
    config.wired_sync = info.wired_sync;
    config.subordinate_delay_ns = info.subordinate_delay_ns;
    config.serial = info.serial;
    config.calibration = info.calibration;
    writers.push_back(std::make_unique<RecordingWriter>(recording_path(out, site.cameras[k].name), config));
    // The folder plays each camera's recording beside it, in the lens its device recorded.
    sim::RgbdCamera& camera = recorded.cameras[k];
    camera.source = "simulated";
    camera.k4a = nlohmann::json::object();
    camera.color = color_lens_for(site.cameras[k], info.color, site_where);
    camera.depth = info.depth;
  }

  RecordSummary summary;
  summary.captures.assign(cameras.size(), 0);
  size_t reported = 0;
  const auto report = [&](const std::string& problem) {
    if (log && reported < kMaxRecordReports) std::fprintf(log, "record: %s\n", problem.c_str());
    ++reported;
  };
  std::vector<bool> stopped(cameras.size(), false);
  std::vector<uint64_t> last_us(cameras.size(), 0);
  start_live_cameras(cameras);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  // The devices run at one rate, so asking each in turn for its next capture keeps up with all.
  while (elapsed_s() < seconds && std::count(stopped.begin(), stopped.end(), false) > 0) {
    size_t timed_out = 0;
    for (size_t k = 0; k < cameras.size(); ++k) {
      if (stopped[k]) continue;
      LiveCamera::Result result;
      try {
        result = cameras[k]->next_capture(kRecordTimeoutMs, true);
      } catch (const LiveError& failure) {
        stopped[k] = true;
        report(std::string(failure.what()) + ": its recording ends here");
        continue;
      }
      if (result.timed_out) {
        ++timed_out;
        continue;
      }
      if (!result.problem.empty() || !result.capture) {
        ++summary.skipped;
        report(result.problem.empty() ? "an empty capture: left out" : result.problem + ": left out");
        continue;
      }
      const uint64_t time = *result.capture->color_device_us;
      if (summary.captures[k] > 0 && time <= last_us[k]) {
        ++summary.skipped;
        report("camera '" + site.cameras[k].name + "': a capture at device time " + std::to_string(time) +
               " us is not after the one before it: left out");
        continue;
      }
      if (k == 0) {
        const RecordingInfo& info = cameras[0]->info();
        const uint64_t delay_us = info.wired_sync == WiredSyncMode::subordinate ? info.subordinate_delay_ns / 1000 : 0;
        const int64_t host_minus_device = int64_t(monotonic_now_us()) - int64_t(time - std::min(time, delay_us));
        if (summary.captures[0] == 0 || host_minus_device < summary.host_minus_device_us)
          summary.host_minus_device_us = host_minus_device;
      }
      writers[k]->write_capture(time, result.color_bytes, result.capture->depth_mm);
      last_us[k] = time;
      ++summary.captures[k];
    }
    if (timed_out > 0 && timed_out == size_t(std::count(stopped.begin(), stopped.end(), false)))
      throw LiveError("record: no camera gave a capture in " + std::to_string(kRecordTimeoutMs) +
                      " ms: check that each is powered and on USB 3, and the wired-sync cables");
  }
  summary.seconds = elapsed_s();
  for (size_t k = 0; k < cameras.size(); ++k) {
    if (summary.captures[k] == 0)
      throw LiveError("record: camera '" + site.cameras[k].name + "' (device '" + settings[k].serial +
                      "') gave no capture to record");
    writers[k]->close();
  }
  sim::write_site(out / "site.json", recorded);
  return summary;
}

}  // namespace rt::camera::k4a
