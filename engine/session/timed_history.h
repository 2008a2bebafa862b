#pragma once
// A short, bounded history of timestamped values shared between threads: the receiver's hand
// thread adds each hand render, the display thread takes the one captured closest in time to a
// portrait (paper: "fuses the images of two representations with the closest timestamp").
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

#include "session/closest_in_time.h"

namespace rt::session {

template <class T>
class TimedHistory {
 public:
  explicit TimedHistory(size_t capacity) : capacity_(capacity == 0 ? 1 : capacity) {}

  // Oldest entries go first once full: a live receiver never needs a render older than that.
  void add(uint64_t timestamp_us, T value) {
    std::lock_guard lock(mutex_);
    entries_.push_back({timestamp_us, std::move(value)});
    while (entries_.size() > capacity_) entries_.pop_front();
  }

  // A copy of the value whose timestamp is closest to `target_us` (the earlier on a tie), with
  // its timestamp; empty while nothing was added.
  std::optional<std::pair<uint64_t, T>> closest(uint64_t target_us) const {
    std::lock_guard lock(mutex_);
    const auto it = closest_in_time(entries_.begin(), entries_.end(), target_us,
                                    [](const Entry& entry) { return entry.timestamp_us; });
    if (it == entries_.end()) return std::nullopt;
    return std::pair<uint64_t, T>{it->timestamp_us, it->value};
  }

  size_t size() const {
    std::lock_guard lock(mutex_);
    return entries_.size();
  }

 private:
  struct Entry {
    uint64_t timestamp_us;
    T value;
  };
  size_t capacity_;
  mutable std::mutex mutex_;
  std::deque<Entry> entries_;
};

}  // namespace rt::session
