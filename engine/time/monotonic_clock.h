#pragma once
// Every frame, skeleton and message carries a timestamp in microseconds of this clock
// (DESIGN.md section 2): monotonic, so that latencies are differences that never go negative.
#include <chrono>
#include <cstdint>

namespace rt {

inline uint64_t monotonic_now_us() {
  return uint64_t(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
}

}  // namespace rt
