#pragma once
// A simulated user's upper body at one instant, in the site frame (metres). The lead's renderer
// turns it into meshes (head sphere, torso box or capsule, arm capsules, the skinned hands) and
// the tracker simulation samples its hands.
#include <Eigen/Core>

#include "tracking/hand_skeleton.h"

namespace rt::sim {

struct ArmPose {
  Eigen::Vector3d shoulder = Eigen::Vector3d::Zero();
  Eigen::Vector3d elbow = Eigen::Vector3d::Zero();
  Eigen::Vector3d wrist = Eigen::Vector3d::Zero();  // equals the hand skeleton's wrist
};

struct PersonPose {
  Eigen::Vector3d head_centre = Eigen::Vector3d::Zero();
  // Site from head (sim/face.h): identity for a user sitting upright, facing the screen; the
  // head leans with the torso, so the face and the eyes on it do too.
  Eigen::Matrix3d head_rotation = Eigen::Matrix3d::Identity();
  double head_radius_m = 0.1;
  // The torso runs from the pelvis to the neck base; it is shoulder_width_m wide (x) and
  // torso_depth_m deep (along the screen's normal when upright).
  Eigen::Vector3d neck_base = Eigen::Vector3d::Zero();
  Eigen::Vector3d pelvis = Eigen::Vector3d::Zero();
  double shoulder_width_m = 0.4;
  double torso_depth_m = 0.22;
  ArmPose left_arm;
  ArmPose right_arm;
  HandSkeleton right_hand;
  HandSkeleton left_hand;
};

// How a user looks: the renderer's colors (linear RGB in [0, 1]) and the size of the hands.
struct UserAppearance {
  Eigen::Vector3f skin_rgb = Eigen::Vector3f(0.80f, 0.62f, 0.50f);
  Eigen::Vector3f shirt_rgb = Eigen::Vector3f(0.15f, 0.25f, 0.55f);
  Eigen::Vector3f shirt_stripe_rgb = Eigen::Vector3f(0.90f, 0.90f, 0.85f);
  double stripe_width_m = 0.03;  // horizontal stripes: texture for the image-based model
  double hand_scale = 1.0;       // 1 = a medium adult hand (about 18 cm wrist to middle tip)
};

}  // namespace rt::sim
