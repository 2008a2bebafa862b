#pragma once
// A site's cameras live: one k4a device per camera (k4a_live_camera.h), their captures put
// together into frame sets by the same rule as a site's recordings (frame_sets.h): a set holds
// the captures within half a frame period of its earliest, at most one per camera, and a camera
// that dropped a frame or gave a bad capture sits out that set while the others go on.
//
// Wired sync: subordinates are started first and the master last, as the SDK requires (a
// subordinate waits for the master's pulses); a subordinate's delay is taken off its times, so
// that all are on the master's clock. Standalone devices each count from their own start: their
// captures are put together by the time since each one's first capture.
#include <atomic>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <algorithm>
#include <string>
#include <vector>

#include "camera/k4a_live_camera.h"
#include "sim/recorded_rgbd_source.h"
#include "sim/rgbd_source.h"
#include "sim/site_description.h"

namespace rt::camera::k4a {

// Opens one device per camera of `site` (same order, same count) after checking that they share
// one frame rate, name distinct devices and have at most one master. Throws LiveError.
std::vector<std::unique_ptr<LiveCamera>> open_live_cameras(const sim::SiteDescription& site,
                                                           const std::vector<LiveCameraSettings>& settings,
                                                           std::shared_ptr<const Library> library = nullptr);
// Starts them, the master last: its first pulse must find every subordinate listening.
void start_live_cameras(const std::vector<std::unique_ptr<LiveCamera>>& cameras);

class LiveSite : public sim::RgbdSource {
 public:
  // Opens every camera of `site` with its settings (same order, same count), checks they share
  // one frame rate and at most one master, and starts them. Throws LiveError. `log` (may be
  // null) gets one line per problem, up to a few.
  LiveSite(const sim::SiteDescription& site, const std::vector<LiveCameraSettings>& settings, std::FILE* log = stderr,
           std::shared_ptr<const Library> library = nullptr);
  ~LiveSite() override;

  // The site with each camera's intrinsics at its modes, from its factory calibration.
  const sim::SiteDescription& site() const { return site_; }
  const std::vector<sim::RecordedRgbdSource::RecordedIntrinsics>& intrinsics() const { return intrinsics_; }
  const std::vector<RecordingInfo>& infos() const { return infos_; }
  // The next frame set, decoded. Empty once every device has stopped giving captures (a device
  // that fails leaves the others going, reported). Throws LiveError when no camera gave a capture
  // within `timeout_ms` of asking. Once the site has shown a set, a camera that gives nothing
  // within two frame periods sits out the set: one silent device does not hold the others back.
  std::optional<sim::RgbdFrame> next_frame() override;
  void set_timeout_ms(int32_t timeout_ms) { timeout_ms_ = timeout_ms; }
  // Captures left out: bad images, or times that did not increase.
  size_t skipped_captures() const { return skipped_; }
  // The devices are waited for and their captures decoded side by side, on up to this many threads.
  void set_decode_threads(unsigned threads) { decode_threads_ = std::max(1u, threads); }

 private:
  struct Camera;
  void report(const std::string& problem);
  void fill(size_t k, int32_t wait_ms);

  sim::SiteDescription site_;
  std::FILE* log_;
  std::vector<std::unique_ptr<LiveCamera>> devices_;
  std::vector<std::unique_ptr<Camera>> cameras_;  // what each device gave and the site has not yet shown
  std::vector<sim::RecordedRgbdSource::RecordedIntrinsics> intrinsics_;
  std::vector<RecordingInfo> infos_;
  uint64_t period_us_ = 0;
  bool standalone_ = true;
  int32_t timeout_ms_ = 2000;
  uint64_t next_index_ = 0;  // of the next set; 0 until one has been shown
  unsigned decode_threads_ = 1;
  std::atomic<size_t> skipped_{0};
  std::mutex report_mutex_;  // the cameras' threads report
  size_t reported_ = 0;
};

}  // namespace rt::camera::k4a
