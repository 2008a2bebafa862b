#pragma once
// Scripted hands for the touch and geometry tests: an open, flat hand facing the screen.
#include <Eigen/Core>

#include "tracking/hand_skeleton.h"

namespace rt::test {

// An open right hand, fingers up (+y), palm centre at (x, y) and every joint at height z above
// the screen plane (z > 0 towards the user); about 9 cm wide and 18 cm tall (wrist to tips).
HandSkeleton flat_hand(double x, double y, double z, uint64_t timestamp_us = 0);

}  // namespace rt::test
