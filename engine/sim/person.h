#pragma once
// The simulated user's body: proportions from the seat and the appearance, and the assembly of
// a full PersonPose from a few driving quantities (torso lean, where each hand is), with the
// arms solved by two-bone inverse kinematics so that they always end at the hands' wrists.
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>

#include "sim/hand_model.h"
#include "sim/person_pose.h"
#include "sim/site_description.h"

namespace rt::sim {

struct BodyGeometry {
  Eigen::Vector3d head_rest = Eigen::Vector3d::Zero();  // the seat's head centre
  Eigen::Vector3d neck_base_rest = Eigen::Vector3d::Zero();
  Eigen::Vector3d pelvis = Eigen::Vector3d::Zero();
  double head_radius_m = 0.1;
  double shoulder_width_m = 0.4;
  double torso_depth_m = 0.22;
  double shoulder_drop_m = 0.03;  // shoulders sit a little below the neck base
  double upper_arm_m = 0.32;
  double forearm_m = 0.28;        // elbow to wrist
  // Reaching forward also slides the shoulder blade forward: metres per radian of lean.
  double protraction_m_per_rad = 0.1;
  double hand_scale = 1.0;
};

// Adult proportions around the seat's head centre. Only the hands take the appearance's scale:
// hand sizes vary more between adults than arm reach does, and every user must reach the glass.
BodyGeometry body_for(const Seat& seat, const UserAppearance& appearance);

// What a motion keyframes. The torso leans towards the screen by `lean_rad`, rotating about
// the pelvis; the head and shoulders go with it.
struct BodyKey {
  double lean_rad = 0.0;
  HandPlacement right;
  HandPlacement left;
};

Eigen::Vector3d shoulder_position(const BodyGeometry& body, double lean_rad, bool right_side);
// Hands resting on the thighs, palms down, fingers loosely curled.
HandPlacement resting_hand(const BodyGeometry& body, bool right_side);

// The elbow from shoulder and wrist: the arm bends down and outwards, as seated arms do. A wrist
// out of reach leaves the arm straight towards it (PersonPose then shows a too-long forearm,
// which the motion tests catch).
ArmPose solve_arm(const BodyGeometry& body, const Eigen::Vector3d& shoulder, const Eigen::Vector3d& wrist,
                  bool right_side);

// A hand this far from the shoulder (fraction of the arm's length) still looks relaxed.
inline constexpr double kComfortableReach = 0.97;
inline constexpr double kMaxLeanRad = 0.6;  // about 34 degrees
// The smallest lean that brings `wrist` within comfortable reach of the shoulder; empty if no
// lean up to kMaxLeanRad does.
std::optional<double> lean_to_reach(const BodyGeometry& body, const Eigen::Vector3d& wrist, bool right_side);

PersonPose pose_person(const BodyGeometry& body, const BodyKey& key, uint64_t timestamp_us);

}  // namespace rt::sim
