#pragma once
// The other site's skeletons carry their capture time on the other machine's clock, which is
// unrelated to this one's. Mapped by the smallest (arrival - stamp) seen lately, a remote capture
// time becomes this clock's capture time plus the link's least delay: the stamps keep their
// spacing (what a fit of the hand's motion needs), and only the link's jitter, never its whole
// delay, ages them.
#include <cstdint>
#include <deque>

namespace rt {

class RemoteClock {
 public:
  // A message stamped `remote_us` arrived at `arrival_us` (this clock); returns its time here.
  uint64_t to_local(uint64_t remote_us, uint64_t arrival_us);

 private:
  // (arrival - stamp) of the latest messages; the least of them is the offset.
  std::deque<int64_t> offsets_us_;
};

}  // namespace rt
