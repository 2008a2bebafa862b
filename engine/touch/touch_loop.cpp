#include "touch/touch_loop.h"

#include "time/monotonic_clock.h"

namespace rt {

TouchLoop::TouchLoop(const TouchParameters& parameters, EventHandler on_event, std::chrono::microseconds period)
    : detector_(parameters), on_event_(std::move(on_event)), period_(period) {}

TouchLoop::~TouchLoop() { stop(); }

void TouchLoop::set_local_hands(std::vector<HandSkeleton> hands) {
  std::lock_guard lock(hands_mutex_);
  local_hands_ = std::move(hands);
}

void TouchLoop::set_remote_hands(std::vector<HandSkeleton> hands) {
  std::lock_guard lock(hands_mutex_);
  remote_hands_ = std::move(hands);
}

std::optional<TouchEvent> TouchLoop::tick(uint64_t now_us) {
  std::vector<HandSkeleton> local, remote;
  {
    std::lock_guard lock(hands_mutex_);
    local = local_hands_;
    remote = remote_hands_;
  }
  std::optional<TouchEvent> event;
  {
    std::lock_guard lock(detector_mutex_);
    event = detector_.update(now_us, local, remote);
  }
  ++ticks_;
  if (event && on_event_) on_event_(*event);
  return event;
}

void TouchLoop::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void TouchLoop::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void TouchLoop::run() {
  // sleep_until a fixed schedule, so that a slow tick does not shift every later one.
  auto next = std::chrono::steady_clock::now();
  while (running_) {
    tick(monotonic_now_us());
    next += period_;
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // fell behind (debugger, overload): skip, do not burst
    std::this_thread::sleep_until(next);
  }
}

}  // namespace rt
