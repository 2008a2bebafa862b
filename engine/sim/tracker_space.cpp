#include "sim/tracker_space.h"

#include <cmath>
#include <limits>

namespace rt::sim {

TrackerHand tracker_hand_from_skeleton(const HandSkeleton& site_hand, double palm_width_m, double arm_width_m,
                                       const TrackerPlacement& placement) {
  const Eigen::Isometry3d to_tracker = placement.tracker_from_site();
  auto point = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(kMillimetresPerMetre * (to_tracker * p)); };
  auto direction = [&](const Eigen::Vector3d& d) { return Eigen::Vector3d(to_tracker.linear() * d); };
  TrackerHand hand;
  hand.id = site_hand.id;
  hand.is_left = site_hand.is_left;
  hand.confidence = site_hand.confidence;
  hand.palm_position = point(site_hand.palm);
  hand.palm_normal = direction(site_hand.palm_normal);
  hand.direction = direction(site_hand.direction);
  hand.wrist = point(site_hand.wrist);
  hand.elbow.reset();
  if (site_hand.has_elbow()) hand.elbow = point(site_hand.elbow);
  hand.palm_width.reset();
  if (std::isfinite(palm_width_m)) hand.palm_width = kMillimetresPerMetre * palm_width_m;
  if (std::isfinite(arm_width_m)) hand.arm_width = kMillimetresPerMetre * arm_width_m;
  for (int d = 0; d < kDigitCount; ++d) {
    const auto& joints = site_hand.digits[d];
    TrackerDigit& digit = hand.digits[d];
    digit.carp = point(joints[int(DigitJoint::Carp)]);
    digit.mcp = point(joints[int(DigitJoint::Mcp)]);
    digit.pip = point(joints[int(DigitJoint::Pip)]);
    digit.dip = point(joints[int(DigitJoint::Dip)]);
    digit.btip = digit.tip = point(joints[int(DigitJoint::Tip)]);
  }
  return hand;
}

HandSkeleton skeleton_from_tracker_hand(const TrackerHand& hand, uint64_t timestamp_us,
                                        const TrackerPlacement& placement) {
  const Eigen::Isometry3d& site_from_tracker = placement.site_from_tracker;
  auto point = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(site_from_tracker * (p / kMillimetresPerMetre)); };
  auto direction = [&](const Eigen::Vector3d& d) {
    return Eigen::Vector3d((site_from_tracker.linear() * d).normalized());
  };
  HandSkeleton skeleton;
  skeleton.timestamp_us = timestamp_us;
  skeleton.id = hand.id;
  skeleton.is_left = hand.is_left;
  skeleton.confidence = float(hand.confidence);
  skeleton.palm = point(hand.palm_position);
  skeleton.wrist = point(hand.wrist);
  if (hand.elbow) skeleton.elbow = point(*hand.elbow);
  if (hand.palm_width) skeleton.palm_width_m = *hand.palm_width / kMillimetresPerMetre;
  if (hand.arm_width) skeleton.arm_width_m = *hand.arm_width / kMillimetresPerMetre;
  skeleton.palm_normal = direction(hand.palm_normal);
  skeleton.direction = direction(hand.direction);
  for (int d = 0; d < kDigitCount; ++d) {
    const TrackerDigit& digit = hand.digits[d];
    auto& joints = skeleton.digits[d];
    joints[int(DigitJoint::Carp)] = point(digit.carp);
    joints[int(DigitJoint::Mcp)] = point(digit.mcp);
    joints[int(DigitJoint::Pip)] = point(digit.pip);
    joints[int(DigitJoint::Dip)] = point(digit.dip);
    // The fingertip, not the distal bone's end: the point that touches.
    joints[int(DigitJoint::Tip)] = point(digit.tip);
  }
  return skeleton;
}

std::vector<HandSkeleton> skeletons_in_site(const TrackerFrame& frame, const TrackerPlacement& placement) {
  std::vector<HandSkeleton> skeletons;
  skeletons.reserve(frame.hands.size());
  for (const TrackerHand& hand : frame.hands)
    skeletons.push_back(skeleton_from_tracker_hand(hand, frame.timestamp_us, placement));
  return skeletons;
}

}  // namespace rt::sim
