#include "touch/remote_clock.h"

#include <algorithm>

namespace rt {
namespace {
// A few seconds of the tracker's stream: long enough to hold a message that crossed the link at its
// quickest, short enough to follow a clock that drifts.
constexpr size_t kRemoteClockWindow = 256;
}  // namespace

uint64_t RemoteClock::to_local(uint64_t remote_us, uint64_t arrival_us) {
  offsets_us_.push_back(int64_t(arrival_us) - int64_t(remote_us));
  while (offsets_us_.size() > kRemoteClockWindow) offsets_us_.pop_front();
  const int64_t offset = *std::min_element(offsets_us_.begin(), offsets_us_.end());
  return uint64_t(std::max<int64_t>(0, int64_t(remote_us) + offset));
}

}  // namespace rt
