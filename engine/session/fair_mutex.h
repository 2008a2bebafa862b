#pragma once
// A first-come, first-served mutex with one express lane. The site's stages take turns on the
// one GPU queue; with a plain std::mutex the capture thread, which re-locks right after
// unlocking, can starve the image-based model and the display for whole seconds on a CPU driver.
// The display takes the express lane (lock_urgent): a received portrait waits for the turn in
// progress only, not behind the sender's queued work, because what is on screen is what the
// remote user's latency is measured by.
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace rt::session {

class FairMutex {
 public:
  void lock() {
    std::unique_lock guard(mutex_);
    const uint64_t ticket = next_ticket_++;
    turn_changed_.wait(guard, [&] { return !busy_ && urgent_waiting_ == 0 && serving_ == ticket; });
    ++serving_;
    busy_ = true;
  }
  // Ahead of every waiter that came through lock(); urgent waiters among themselves in no order.
  void lock_urgent() {
    std::unique_lock guard(mutex_);
    ++urgent_waiting_;
    turn_changed_.wait(guard, [&] { return !busy_; });
    --urgent_waiting_;
    busy_ = true;
  }
  // Threads waiting now (for tests and diagnostics).
  uint64_t waiting() {
    std::lock_guard guard(mutex_);
    return (next_ticket_ - serving_) + urgent_waiting_;
  }
  void unlock() {
    {
      std::lock_guard guard(mutex_);
      busy_ = false;
    }
    turn_changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable turn_changed_;
  uint64_t next_ticket_ = 0, serving_ = 0;
  uint64_t urgent_waiting_ = 0;
  bool busy_ = false;
};

// std::lock_guard for the express lane.
class UrgentTurn {
 public:
  explicit UrgentTurn(FairMutex& mutex) : mutex_(mutex) { mutex_.lock_urgent(); }
  ~UrgentTurn() { mutex_.unlock(); }
  UrgentTurn(const UrgentTurn&) = delete;
  UrgentTurn& operator=(const UrgentTurn&) = delete;

 private:
  FairMutex& mutex_;
};

}  // namespace rt::session
