#include "tracking/hand_skeleton.h"

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

}  // namespace rt
