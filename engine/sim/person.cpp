#include "sim/person.h"

#include <algorithm>
#include <cmath>

namespace rt::sim {

namespace {

Eigen::Matrix3d lean_rotation(double lean_rad) {
  // Leaning towards the screen moves the neck towards -z: a rotation about -x.
  return Eigen::AngleAxisd(-lean_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
}

double side_sign(bool right_side) { return right_side ? 1.0 : -1.0; }  // the user's right is +x

}  // namespace

BodyGeometry body_for(const Seat& seat, const UserAppearance& appearance) {
  BodyGeometry body;
  body.hand_scale = appearance.hand_scale;
  body.head_rest = seat.head_centre_m;
  // Eye height to the base of the neck, and a slight backward slant of the seated torso.
  body.neck_base_rest = seat.head_centre_m + Eigen::Vector3d(0.0, -0.22, 0.03);
  body.pelvis = body.neck_base_rest + Eigen::Vector3d(0.0, -0.52, 0.04);
  return body;
}

Eigen::Vector3d shoulder_position(const BodyGeometry& body, double lean_rad, bool right_side) {
  const Eigen::Matrix3d lean = lean_rotation(lean_rad);
  const Eigen::Vector3d neck = body.pelvis + lean * (body.neck_base_rest - body.pelvis);
  return neck + lean * Eigen::Vector3d(side_sign(right_side) * body.shoulder_width_m / 2, -body.shoulder_drop_m,
                                       -body.protraction_m_per_rad * lean_rad);
}

HandPlacement resting_hand(const BodyGeometry& body, bool right_side) {
  HandPlacement hand;
  hand.palm = body.pelvis + Eigen::Vector3d(side_sign(right_side) * 0.16, 0.13, -0.24);
  hand.orientation = hand_orientation(-Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY());
  hand.curl = 0.35;
  return hand;
}

ArmPose solve_arm(const BodyGeometry& body, const Eigen::Vector3d& shoulder, const Eigen::Vector3d& wrist,
                  bool right_side) {
  ArmPose arm{shoulder, shoulder, wrist};
  const double a = body.upper_arm_m, b = body.forearm_m;
  const Eigen::Vector3d to_wrist = wrist - shoulder;
  const double reach = to_wrist.norm();
  if (!(reach > 1e-9)) return arm;
  const Eigen::Vector3d along = to_wrist / reach;
  // Law of cosines; the distance is clamped so that an unreachable wrist straightens the arm.
  const double d = std::clamp(reach, std::abs(a - b) + 1e-9, a + b);
  const double cos_shoulder = std::clamp((a * a + d * d - b * b) / (2 * a * d), -1.0, 1.0);
  const Eigen::Vector3d pole(side_sign(right_side) * 0.35, -1.0, 0.25);
  Eigen::Vector3d bend = pole - along * along.dot(pole);
  if (bend.norm() < 1e-6) bend = Eigen::Vector3d::UnitZ() - along * along.z();  // arm pointing along the pole
  bend.normalize();
  arm.elbow = shoulder + a * (cos_shoulder * along + std::sqrt(1.0 - cos_shoulder * cos_shoulder) * bend);
  return arm;
}

std::optional<double> lean_to_reach(const BodyGeometry& body, const Eigen::Vector3d& wrist, bool right_side) {
  const double comfortable = kComfortableReach * (body.upper_arm_m + body.forearm_m);
  constexpr int kSteps = 500;
  for (int i = 0; i <= kSteps; ++i) {
    const double lean = kMaxLeanRad * i / kSteps;
    if ((wrist - shoulder_position(body, lean, right_side)).norm() <= comfortable) return lean;
  }
  return std::nullopt;
}

PersonPose pose_person(const BodyGeometry& body, const BodyKey& key, uint64_t timestamp_us) {
  const Eigen::Matrix3d lean = lean_rotation(key.lean_rad);
  PersonPose pose;
  pose.pelvis = body.pelvis;
  pose.neck_base = body.pelvis + lean * (body.neck_base_rest - body.pelvis);
  pose.head_centre = body.pelvis + lean * (body.head_rest - body.pelvis);
  pose.head_rotation = lean;
  pose.head_radius_m = body.head_radius_m;
  pose.shoulder_width_m = body.shoulder_width_m;
  pose.torso_depth_m = body.torso_depth_m;

  pose.right_hand = build_hand(key.right, false, body.hand_scale);
  pose.left_hand = build_hand(key.left, true, body.hand_scale);
  pose.right_arm = solve_arm(body, shoulder_position(body, key.lean_rad, true), pose.right_hand.wrist, true);
  pose.left_arm = solve_arm(body, shoulder_position(body, key.lean_rad, false), pose.left_hand.wrist, false);
  pose.right_hand.elbow = pose.right_arm.elbow;
  pose.left_hand.elbow = pose.left_arm.elbow;
  pose.right_hand.timestamp_us = pose.left_hand.timestamp_us = timestamp_us;
  return pose;
}

}  // namespace rt::sim
