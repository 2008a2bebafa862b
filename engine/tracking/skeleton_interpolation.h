#pragma once
// The remote user's hands at a given moment, from the tracker's samples around it (50 Hz): the
// receiver poses the geometry hand for the capture time of the portrait it fuses it with, so the
// two representations show the same moment (paper section 3.3, "the closest timestamp"), however
// the portrait's and the skeleton's deliveries interleave.
//
// Rules, per hand (matched across samples by tracker id and side):
//  - a sample is usable for time t when it lies within `max_gap_us` of t;
//  - when both samples bracketing t are usable and both hold the hand, the hand is interpolated:
//    joint positions linearly, the palm's orientation (direction, normal) by a quaternion slerp;
//  - otherwise the sample nearer t (the earlier on a tie) decides alone: the hand as it is there
//    if that sample is usable and holds it, else no hand. A hand present in one sample only is
//    never blended with nothing, and a t before the first or after the last sample holds the
//    nearest one while it is within the limit;
//  - when no sample is within the limit the result is "no hand" (stale), not an old pose.
// A joint that is not finite in a sample (a missing elbow is NaN) is taken from the nearer
// sample as it is there, NaN included; it never spreads to the other joints.
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "tracking/hand_skeleton.h"

namespace rt {

// Beyond this the hand may have moved anywhere: a stale pose would put it where it no longer is.
inline constexpr uint64_t kMaxSkeletonGapUs = 100'000;

// One tracker sample: every hand tracked at that moment.
struct SkeletonSample {
  uint64_t timestamp_us = 0;
  std::vector<HandSkeleton> hands;
};

struct HandsAtTime {
  // The hands at the asked time, in the order of the sample nearer to it; empty when none was
  // tracked then, or nothing is known about that moment (`stale()`). An interpolated hand's
  // timestamp_us is the asked time, a held one keeps its sample's: the moment its pose shows.
  std::vector<HandSkeleton> hands;
  // Per hand, the residual gap: how far in time the pose reaches to the samples it was built
  // from, the farther of the two when interpolated, |t - sample| when one sample is held; 0 for
  // a sample exactly at t. Never above the limit.
  std::vector<uint64_t> gap_us;
  std::vector<bool> interpolated;  // per hand: between two samples, rather than one held
  // |t - the nearest sample|; empty when there are no samples at all.
  std::optional<uint64_t> nearest_sample_gap_us;
  uint64_t max_gap_us = kMaxSkeletonGapUs;

  // No sample within the limit (or none at all): the moment's hands are unknown.
  bool stale() const { return !nearest_sample_gap_us || *nearest_sample_gap_us > max_gap_us; }
};

// The hand between `a` (s = 0) and `b` (s = 1), the same hand at two moments; the timestamp is
// interpolated too. Positions lerp; a joint not finite in either sample comes from the nearer one
// (s < 0.5: `a`); the palm's frame slerps, or comes from the nearer sample when either frame is
// degenerate. Confidence lerps; id and side are `a`'s.
HandSkeleton interpolate_hand(const HandSkeleton& a, const HandSkeleton& b, double s);

// The hands at `t_us` from samples in increasing time order (throws std::invalid_argument
// otherwise: the caller keeps them in order, e.g. in a SkeletonHistory).
HandsAtTime hands_at(std::span<const SkeletonSample> samples, uint64_t t_us, uint64_t max_gap_us = kMaxSkeletonGapUs);

// A bounded, time-ordered history of samples shared between threads: the network thread adds
// each arrival (out of order after a reconnect or a reordering link, so it inserts in order; a
// repeated timestamp replaces the earlier copy), the display thread asks for any moment.
class SkeletonHistory {
 public:
  explicit SkeletonHistory(size_t capacity, uint64_t max_gap_us = kMaxSkeletonGapUs);

  // The oldest sample goes once full; a sample older than all kept ones is then not taken.
  void add(SkeletonSample sample);
  HandsAtTime at(uint64_t t_us) const;
  size_t size() const;
  uint64_t max_gap_us() const { return max_gap_us_; }

 private:
  size_t capacity_;
  uint64_t max_gap_us_;
  mutable std::mutex mutex_;
  std::vector<SkeletonSample> samples_;  // increasing timestamps
};

}  // namespace rt
