#pragma once
// At most one line a second per kind of event, with how many were not logged since: a peer or a
// stranger that provokes refusals, sheds or rejections must not flood the log, nor cost the
// network thread the formatting of lines no one will see.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <type_traits>

namespace rt::net {

class LogLimit {
 public:
  explicit LogLimit(std::function<void(const std::string&)> log) : log_(std::move(log)) {}

  void operator()(const std::string& kind, const std::string& line) {
    (*this)(kind, [&] { return line; });
  }
  // `make_line` is called only when the line is due.
  template <typename MakeLine>
    requires std::is_invocable_r_v<std::string, MakeLine>
  void operator()(const std::string& kind, MakeLine&& make_line) {
    std::lock_guard lock(mutex_);  // the portrait decoder's thread rejects too
    Kind& limit = kinds_[kind];
    const auto now = std::chrono::steady_clock::now();
    if (limit.last != std::chrono::steady_clock::time_point{} && now - limit.last < std::chrono::seconds(1)) {
      ++limit.suppressed;
      return;
    }
    log_(make_line() +
         (limit.suppressed ? " (and " + std::to_string(limit.suppressed) + " more like it in the last second)" : ""));
    limit.suppressed = 0;
    limit.last = now;
  }

 private:
  struct Kind {
    std::chrono::steady_clock::time_point last{};
    uint64_t suppressed = 0;
  };
  std::function<void(const std::string&)> log_;
  std::map<std::string, Kind> kinds_;
  std::mutex mutex_;
};

}  // namespace rt::net
