#pragma once
// Frame sets of several cameras that each record on their own: a set holds the captures taken
// within half a frame period of its earliest one, at most one per camera. A camera that dropped a
// frame is absent from that set; nothing waits for it, so a set is never held back.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace rt::camera {

struct FrameSet {
  uint64_t time_us = 0;                         // the earliest capture's time
  std::vector<std::optional<size_t>> captures;  // per camera: the ordinal of its capture, if any
};

// `capture_times_us[k]`: camera k's capture times, increasing, on one clock. The sets' times
// then never decrease.
std::vector<FrameSet> assemble_frame_sets(const std::vector<std::vector<uint64_t>>& capture_times_us,
                                          uint64_t frame_period_us);

}  // namespace rt::camera
