#pragma once
// The device boundary (DESIGN.md section 2): site-frame skeletons (metres) to the tracker's own
// space (millimetres, Leap axes) and back, through the tracker placement of the site description.
#include <vector>

#include "sim/site_description.h"
#include "sim/tracker_frame.h"
#include "tracking/hand_skeleton.h"

namespace rt::sim {

inline constexpr double kMillimetresPerMetre = 1000.0;

// What the simulated device reports for a hand; `palm_width_m` is the hand's width, `arm_width_m`
// the forearm's (NaN: the device reports none). A non-finite elbow is reported as none.
TrackerHand tracker_hand_from_skeleton(const HandSkeleton& site_hand, double palm_width_m, double arm_width_m,
                                       const TrackerPlacement& placement);
// The conversion every consumer of tracker data goes through: a hand without an elbow or an arm
// width gets NaN there.
HandSkeleton skeleton_from_tracker_hand(const TrackerHand& hand, uint64_t timestamp_us,
                                        const TrackerPlacement& placement);
std::vector<HandSkeleton> skeletons_in_site(const TrackerFrame& frame, const TrackerPlacement& placement);

}  // namespace rt::sim
