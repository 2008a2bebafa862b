#pragma once
// The bounded hand-off between a site's threads (capture -> image-based model, network ->
// display): one slot, newest wins. A producer never waits for a slow consumer; a frame the
// consumer has not taken when the next one arrives is stale and is dropped (and counted), as in
// a live system, where showing an old frame late is worse than skipping it.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

namespace rt::session {

template <class T>
class Mailbox {
 public:
  // Returns true when it replaced a value nobody had taken (a dropped frame).
  bool put(T value) {
    bool replaced;
    {
      std::lock_guard lock(mutex_);
      replaced = value_.has_value();
      if (replaced) ++dropped_;
      value_ = std::move(value);
      ++put_;
    }
    ready_.notify_one();
    return replaced;
  }

  std::optional<T> take() {
    std::lock_guard lock(mutex_);
    return take_locked();
  }

  // Waits up to `timeout` for a value; empty on timeout or once closed and empty.
  std::optional<T> wait_take(std::chrono::microseconds timeout) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [&] { return value_.has_value() || closed_; });
    return take_locked();
  }

  // Wakes every waiter; later puts are still kept (a consumer may drain them).
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }
  bool closed() const {
    std::lock_guard lock(mutex_);
    return closed_;
  }

  uint64_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }
  uint64_t delivered() const {
    std::lock_guard lock(mutex_);
    return taken_;
  }
  uint64_t offered() const {
    std::lock_guard lock(mutex_);
    return put_;
  }

 private:
  std::optional<T> take_locked() {
    std::optional<T> out = std::move(value_);
    value_.reset();
    if (out) ++taken_;
    return out;
  }

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::optional<T> value_;
  bool closed_ = false;
  uint64_t dropped_ = 0, taken_ = 0, put_ = 0;
};

}  // namespace rt::session
