#include "camera/frame_sets.h"

#include <algorithm>
#include <limits>

namespace rt::camera {

std::vector<FrameSet> assemble_frame_sets(const std::vector<std::vector<uint64_t>>& capture_times_us,
                                          uint64_t frame_period_us) {
  const size_t cameras = capture_times_us.size();
  std::vector<size_t> next(cameras, 0);
  std::vector<FrameSet> sets;
  while (true) {
    uint64_t earliest = std::numeric_limits<uint64_t>::max();
    for (size_t k = 0; k < cameras; ++k)
      if (next[k] < capture_times_us[k].size()) earliest = std::min(earliest, capture_times_us[k][next[k]]);
    if (earliest == std::numeric_limits<uint64_t>::max()) break;
    FrameSet set;
    set.time_us = earliest;
    set.captures.resize(cameras);
    // Each set takes at least the earliest capture, so every pass consumes one: no input spins.
    for (size_t k = 0; k < cameras; ++k)
      if (next[k] < capture_times_us[k].size() && capture_times_us[k][next[k]] - earliest < (frame_period_us + 1) / 2)
        set.captures[k] = next[k]++;
    sets.push_back(std::move(set));
  }
  return sets;
}

}  // namespace rt::camera
