#pragma once
// The receiver fuses a portrait with the remote skeleton captured closest in time to it (paper:
// "fuses the images of two representations with the closest timestamp").
#include <cstdint>
#include <cstdlib>

namespace rt::session {

// The element of [first, last) whose timestamp (`timestamp_of(element)`, microseconds) is
// closest to `target_us`; the earlier one on a tie; `last` when the range is empty.
template <class Iterator, class TimestampOf>
Iterator closest_in_time(Iterator first, Iterator last, uint64_t target_us, TimestampOf timestamp_of) {
  Iterator best = last;
  uint64_t best_gap = UINT64_MAX;
  for (Iterator it = first; it != last; ++it) {
    const uint64_t t = timestamp_of(*it);
    const uint64_t gap = t > target_us ? t - target_us : target_us - t;
    if (gap < best_gap) best = it, best_gap = gap;
  }
  return best;
}

}  // namespace rt::session
