#pragma once
// The hand's distance to the screen as the paper measures it (DESIGN.md section 3): the mean over
// its finite joints (wrist, palm, every digit joint) of their distances to the screen plane. It
// drives the fusion ramp (Eq. 4) and the touch phases.
#include "tracking/hand_skeleton.h"

namespace rt {

// NaN when no joint is finite: "no hand", never a distance.
double hand_distance_to_screen(const HandSkeleton& hand);

}  // namespace rt
