#include "support/hands.h"

namespace rt::test {

HandSkeleton flat_hand(double x, double y, double z, uint64_t timestamp_us) {
  HandSkeleton hand;
  hand.timestamp_us = timestamp_us;
  hand.confidence = 1.0f;
  hand.palm = {x, y, z};
  hand.wrist = {x, y - 0.06, z};
  hand.elbow = {x, y - 0.3, z + 0.2};
  hand.palm_normal = {0, 0, -1};  // facing the screen
  hand.direction = {0, 1, 0};
  // Digit bases spread across the palm; the thumb off to the side at an angle.
  const double base_x[kDigitCount] = {-0.045, -0.03, -0.01, 0.01, 0.03};
  const double lengths[kDigitCount] = {0.06, 0.09, 0.1, 0.095, 0.075};
  for (int d = 0; d < kDigitCount; ++d) {
    const Eigen::Vector3d carp(x + base_x[d] * 0.5, y - 0.05, z);
    const Eigen::Vector3d mcp(x + base_x[d], y + (d == 0 ? -0.02 : 0.03), z);
    const Eigen::Vector3d along = d == 0 ? Eigen::Vector3d(-0.7, 0.7, 0).normalized() : Eigen::Vector3d(0, 1, 0);
    hand.digits[d][int(DigitJoint::Carp)] = d == 0 ? mcp : carp;  // zero-length thumb metacarpal
    hand.digits[d][int(DigitJoint::Mcp)] = mcp;
    hand.digits[d][int(DigitJoint::Pip)] = mcp + along * lengths[d] * 0.45;
    hand.digits[d][int(DigitJoint::Dip)] = mcp + along * lengths[d] * 0.75;
    hand.digits[d][int(DigitJoint::Tip)] = mcp + along * lengths[d];
  }
  return hand;
}

}  // namespace rt::test
