#include "tracking/hand_skeleton.h"

#include <cmath>

namespace rt {

std::vector<Eigen::Vector3d> HandSkeleton::hand_joints() const {
  std::vector<Eigen::Vector3d> joints;
  joints.reserve(2 + kDigitCount * kJointsPerDigit);
  joints.push_back(wrist);
  joints.push_back(palm);
  for (const auto& digit : digits)
    for (const auto& point : digit) joints.push_back(point);
  return joints;
}

const HandSkeleton* hand_nearest_screen(const std::vector<HandSkeleton>& hands) {
  const HandSkeleton* best = nullptr;
  for (const auto& hand : hands)
    if (std::isfinite(hand.palm.z()) && (!best || std::abs(hand.palm.z()) < std::abs(best->palm.z()))) best = &hand;
  return best;
}

}  // namespace rt
