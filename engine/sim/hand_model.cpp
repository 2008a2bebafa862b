#include "sim/hand_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rt::sim {

namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
constexpr double kPalmWidthM = 0.085;

}  // namespace

const std::array<DigitModel, kDigitCount>& medium_adult_hand() {
  // Bone lengths after anthropometric tables of adult hands (about 18 cm wrist to middle tip,
  // 8.5 cm palm width). The thumb's "proximal" bone is its anatomical metacarpal, as in Leap's
  // model, whose thumb metacarpal has zero length (carp == mcp).
  static const std::array<DigitModel, kDigitCount> hand{{
      {{0.022, 0.022}, {0.022, 0.022}, 50.0, {0.046, 0.032, 0.026}, {25.0, 45.0, 60.0}},   // thumb
      {{0.012, 0.012}, {0.025, 0.085}, 6.0, {0.040, 0.023, 0.019}, {70.0, 95.0, 60.0}},    // index
      {{0.002, 0.012}, {0.005, 0.088}, 0.0, {0.045, 0.027, 0.020}, {70.0, 95.0, 60.0}},    // middle
      {{-0.010, 0.012}, {-0.014, 0.083}, -5.0, {0.042, 0.026, 0.020}, {70.0, 95.0, 60.0}}, // ring
      {{-0.020, 0.010}, {-0.031, 0.074}, -11.0, {0.033, 0.019, 0.018}, {70.0, 95.0, 60.0}} // pinky
  }};
  return hand;
}

double medium_hand_length_m() {
  const DigitModel& middle = medium_adult_hand()[int(Digit::Middle)];
  const double splay = middle.splay_deg * kRadiansPerDegree;
  const double finger = middle.phalanges_m[0] + middle.phalanges_m[1] + middle.phalanges_m[2];
  return (middle.mcp_uv + finger * Eigen::Vector2d(std::sin(splay), std::cos(splay))).norm();
}

double palm_width_m(double hand_scale) { return kPalmWidthM * hand_scale; }

Eigen::Vector2d palm_centre_uv() { return {0.0, 0.05}; }

Eigen::Quaterniond hand_orientation(const Eigen::Vector3d& direction, const Eigen::Vector3d& palm_normal) {
  const Eigen::Vector3d v = direction.normalized();
  const Eigen::Vector3d w = (palm_normal - v * v.dot(palm_normal)).normalized();
  Eigen::Matrix3d rotation;
  rotation << v.cross(w), v, w;
  return Eigen::Quaterniond(rotation).normalized();
}

HandSkeleton build_hand(const HandPlacement& placement, bool is_left, double hand_scale) {
  const Eigen::Matrix3d rotation = placement.orientation.normalized().toRotationMatrix();
  const double mirror = is_left ? -1.0 : 1.0;
  const Eigen::Vector3d u = mirror * rotation.col(0), v = rotation.col(1), w = rotation.col(2);
  const Eigen::Vector2d palm_uv = palm_centre_uv();
  auto in_site = [&](const Eigen::Vector2d& uv) {
    return Eigen::Vector3d(placement.palm + hand_scale * ((uv.x() - palm_uv.x()) * u + (uv.y() - palm_uv.y()) * v));
  };

  HandSkeleton hand;
  hand.is_left = is_left;
  hand.confidence = 1.0f;
  hand.palm = placement.palm;
  hand.wrist = in_site({0.0, 0.0});
  hand.palm_normal = w;
  hand.direction = v;
  for (int d = 0; d < kDigitCount; ++d) {
    const DigitModel& model = medium_adult_hand()[d];
    auto& joints = hand.digits[d];
    joints[int(DigitJoint::Carp)] = in_site(model.carp_uv);
    joints[int(DigitJoint::Mcp)] = in_site(model.mcp_uv);
    const double splay = model.splay_deg * kRadiansPerDegree;
    const Eigen::Vector3d straight = std::sin(splay) * u + std::cos(splay) * v;
    // Flexing bends the digit about an axis in the palm plane, towards the palm side (+w).
    const Eigen::Vector3d flexion_axis = straight.cross(w).normalized();
    const double curl = std::clamp(placement.curl + placement.extra_curl[size_t(d)], 0.0, 1.0);
    double flexion = 0.0;
    Eigen::Vector3d joint = joints[int(DigitJoint::Mcp)];
    for (int bone = 0; bone < 3; ++bone) {
      flexion += curl * model.max_flexion_deg[bone] * kRadiansPerDegree;
      joint += hand_scale * model.phalanges_m[bone] * (Eigen::AngleAxisd(flexion, flexion_axis) * straight);
      joints[int(DigitJoint::Pip) + bone] = joint;
    }
  }
  return hand;
}

}  // namespace rt::sim
