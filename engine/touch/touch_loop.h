#pragma once
// Runs the mutual touch detector at 50 Hz in its own thread on the newest skeletons of both
// sides, and hands each event to a callback (which pulses the motor). Skeletons arrive from
// other threads (tracker, network) into newest-value slots: a stale skeleton is replaced, never
// queued.
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "touch/mutual_touch.h"

namespace rt {

class TouchLoop {
 public:
  using EventHandler = std::function<void(const TouchEvent&)>;

  TouchLoop(const TouchParameters& parameters, EventHandler on_event,
            std::chrono::microseconds period = std::chrono::microseconds(20'000));
  ~TouchLoop();  // stops the thread
  TouchLoop(const TouchLoop&) = delete;
  TouchLoop& operator=(const TouchLoop&) = delete;

  // Newest hands of each side, both in the local site frame and the local clock.
  void set_local_hands(std::vector<HandSkeleton> hands);
  void set_remote_hands(std::vector<HandSkeleton> hands);

  // One detection step at `now_us`, as the thread runs it; for tests and for callers that
  // drive their own clock.
  std::optional<TouchEvent> tick(uint64_t now_us);

  void start();
  void stop();
  uint64_t ticks() const { return ticks_.load(); }

 private:
  void run();

  MutualTouchDetector detector_;
  EventHandler on_event_;
  std::chrono::microseconds period_;
  std::mutex hands_mutex_;
  std::vector<HandSkeleton> local_hands_, remote_hands_;
  std::mutex detector_mutex_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> ticks_{0};
  std::thread thread_;
};

}  // namespace rt
