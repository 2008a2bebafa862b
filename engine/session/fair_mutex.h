#pragma once
// A first-come, first-served mutex. The site's stages take turns on the one GPU queue; with a
// plain std::mutex the capture thread, which re-locks right after unlocking, can starve the
// image-based model and the display for whole seconds on a CPU driver.
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace rt::session {

class FairMutex {
 public:
  void lock() {
    std::unique_lock guard(mutex_);
    const uint64_t ticket = next_ticket_++;
    turn_changed_.wait(guard, [&] { return serving_ == ticket; });
  }
  void unlock() {
    {
      std::lock_guard guard(mutex_);
      ++serving_;
    }
    turn_changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable turn_changed_;
  uint64_t next_ticket_ = 0, serving_ = 0;
};

}  // namespace rt::session
