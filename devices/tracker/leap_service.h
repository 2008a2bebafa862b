#pragma once
// The Leap Motion service live, over its WebSocket protocol (DESIGN.md section 6): a client thread
// connects to ws://HOST:PORT/PATH (the service's default ws://127.0.0.1:6437/v6.json), asks for
// frames in the background and focused, reads each message as one frame (sim/leap_json.h, which
// derives the fields a service version leaves out), keeps the newest, and reconnects after the
// service goes away. Malformed, oversized and other messages are counted and survived: a message
// over the size bound ends the connection (it is not buffered) and the client reconnects.
// Owns no Vulkan objects; thread-safe.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "sim/tracker_frame.h"
#include "tracker/leap_url.h"

namespace rt::devices {


enum class LeapState { Connecting, Connected, Lost };
const char* leap_state_name(LeapState state);  // "connecting", "connected", "lost"

struct LeapServiceStatus {
  LeapState state = LeapState::Connecting;
  uint64_t connections = 0;         // handshakes that succeeded
  uint64_t frames = 0;              // frames parsed
  uint64_t frames_with_hands = 0;
  uint64_t messages_malformed = 0;  // not JSON, or a frame refused by the parser
  uint64_t messages_oversized = 0;  // over the bound: the connection was dropped
  uint64_t messages_other = 0;      // JSON that is not a frame (the version message, events)
  uint64_t first_frame_us = 0, last_frame_us = 0;  // monotonic, when the first and the newest arrived
  std::string service_version;      // from the service's first message, when it sent one
  std::string last_error;           // the last connection error or refused message
  // The rate the frames arrived at, between the first and the newest; none before two frames.
  std::optional<double> frames_per_second() const;
  nlohmann::json to_json() const;
};

class LeapServiceTracker {
 public:
  struct Options {
    std::string url = kDefaultLeapUrl;
    size_t max_message_bytes = size_t(1) << 20;  // a frame of two hands is a few kB
    std::chrono::milliseconds reconnect_delay{250};
    std::chrono::milliseconds connect_timeout{2000};  // one attempt's TCP connect and handshake
  };
  // Starts the client thread at once. Throws std::invalid_argument for a bad URL.
  explicit LeapServiceTracker(Options options);
  ~LeapServiceTracker();  // stops the thread, closing the connection
  LeapServiceTracker(const LeapServiceTracker&) = delete;
  LeapServiceTracker& operator=(const LeapServiceTracker&) = delete;

  // Blocks until a handshake has succeeded or `timeout` passed; throws std::runtime_error naming
  // the URL and the last error ("no Leap service answers at ws://...: Connection refused").
  void wait_connected(std::chrono::milliseconds timeout);

  struct Received {
    sim::TrackerFrame frame;
    uint64_t received_us = 0;  // rt::monotonic_now_us() when it arrived
    uint64_t sequence = 0;     // frames received before it, plus one
  };
  std::optional<Received> newest() const;
  LeapServiceStatus status() const;
  const LeapUrl& url() const { return url_; }

 private:
  class Connection;
  void run();
  void handle_message(const std::string& text);
  void set_error(const std::string& error);

  Options options_;
  LeapUrl url_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  LeapServiceStatus status_;
  std::optional<Received> newest_;
  std::atomic<bool> stopping_{false};
  std::shared_ptr<void> io_;  // the running connection's io_context, to stop it from the destructor
  std::thread thread_;
};

}  // namespace rt::devices
