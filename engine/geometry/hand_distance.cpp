#include "geometry/hand_distance.h"

#include <cmath>

#include "geometry/site_frames.h"

namespace rt {

double hand_distance_to_screen(const HandSkeleton& hand) {
  double sum = 0;
  size_t counted = 0;
  for (const auto& joint : hand.hand_joints())
    if (joint.allFinite()) sum += distance_to_screen(joint), ++counted;
  return counted ? sum / double(counted) : NAN;
}

}  // namespace rt
