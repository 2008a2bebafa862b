#pragma once
// What the sender, the receiver and the run of one site share: the options, the scene, the
// device and its GPU turn, the event log, the link and the scene clock. The run owns it; the
// sender and the receiver hold a reference.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

#include "image/host_image.h"
#include "net/transport.h"
#include "session/event_log.h"
#include "session/fair_mutex.h"
#include "sim/scene.h"
#include "site/site_options.h"
#include "site/site_capture.h"
#include "vulkan/context.h"
#include "vulkan/frame_graph.h"

namespace rt::display {
class GlfwWindow;
}

namespace rt::site {

// SIGINT or SIGTERM has asked the site to stop (site_run.cpp notes it).
bool stop_signal_received();

struct SiteCommon {
  SiteRunOptions options;
  std::string name;  // "A" or "B"
  Site remote = Site::B;
  sim::Scene scene;  // a replay replaces this site's description, frame count and rate (the sender does)
  uint32_t width = 0, height = 0;  // of the portraits and the display
  std::filesystem::path out;
  vk::Context* context = nullptr;
  session::FairMutex gpu_turn;  // lavapipe is one queue on the CPU: GPU work from all threads takes turns
  session::EventLog* events = nullptr;
  net::Transport* net = nullptr;  // the direct session or the WebRTC call (options.transport)
  SiteCapture* capture = nullptr;  // --capture-frame: the sender's and the receiver's iteration
  HostImage background;  // what the display shows behind the remote user
  display::GlfwWindow* window = nullptr;       // --display window or both; polled by the run's main thread
  bool write_frames = true;                    // PNG and MP4 (--display headless or both)
  const vk::FrameGraph* sender_graph = nullptr;  // the image-based model's, for the window's debug views

  // The scene clock: scene time = (now - epoch) * time_scale from the moment the sites connect.
  uint64_t epoch_us = 0, end_us = 0;
  std::atomic<bool> stopping{false};
  std::atomic<bool> sender_done{false};  // no more portraits will be sent
  // The search for the user's eyes before the call ends here at the latest (the connect
  // timeout, counted from the site's start), or at a stop signal; it goes on during the call.
  uint64_t eye_search_deadline_us = UINT64_MAX;

  double scene_time_s(uint64_t now_us) const { return double(now_us - epoch_us) * 1e-6 * options.time_scale; }
  // The monotonic time at which the scene clock reads `scene_s` (the inverse of scene_time_s).
  uint64_t wall_us_at_scene_time(double scene_s) const {
    return epoch_us + uint64_t(std::llround(std::max(scene_s, 0.0) / options.time_scale * 1e6));
  }
  const sim::SiteDescription& site() const { return scene.at(options.site).site; }

  // Per-pass GPU ms of a stage's graph, for metrics.json.
  void record_gpu_ms(const std::string& stage, const vk::FrameGraph& graph);
  nlohmann::json gpu_ms() const;

 private:
  mutable std::mutex gpu_ms_mutex_;
  nlohmann::json gpu_ms_ = nlohmann::json::object();
};

}  // namespace rt::site
