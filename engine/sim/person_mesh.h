#pragma once
// Triangle meshes of a simulated user, for the person_raster pass: a head, neck, torso and arms
// (part BODY; striped shirt, skin-colored head and forearms, the face photograph on the front of
// the head: sim/face.h) and the hands (part HAND), each
// bone a capsule whose axis runs exactly through the tracked joints, so that the rendered hand
// and the tracker's skeleton agree.
#include <vector>

#include "shared/config.h"
#include "sim/person_pose.h"

namespace rt::sim {

using shader_abi::MeshVertex;

// The simulated user's forearm: a skin-colored capsule of this radius from elbow to wrist. The
// simulated tracker reports twice it as the arm's width.
inline constexpr double kForearmRadiusM = 0.035;
inline constexpr double kArmWidthM = 2 * kForearmRadiusM;

// A stripe period below zero marks the head's vertices: their stripe color is then (u, v,
// facing) on the face texture, which person_raster samples (person_raster.frag).
inline constexpr float kFaceTexturePeriod = -1.0f;

struct MeshDetail {
  int segments = 16;  // around a capsule or sphere
  int rings = 8;      // from a capsule's pole to its equator
};

// Appends a capsule from a to b with an elliptic cross-section (radius_u along `u_hint`'s part
// orthogonal to the axis, radius_v across); `part`, colors and stripes as MeshVertex says.
void append_capsule(std::vector<MeshVertex>& mesh, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_u,
                    double radius_v, const Eigen::Vector3d& u_hint, float part, const Eigen::Vector3f& color,
                    const Eigen::Vector3f& stripe_color, float stripe_period_m, const MeshDetail& detail = {});

// Appends the hand: a capsule per bone (metacarpals and phalanges) and a flat palm.
void append_hand(std::vector<MeshVertex>& mesh, const HandSkeleton& hand, double hand_scale,
                 const Eigen::Vector3f& skin_rgb, const MeshDetail& detail = {});

// The simulated forearm: a skin-colored capsule of kForearmRadiusM from the elbow to the wrist.
void append_forearm(std::vector<MeshVertex>& mesh, const ArmPose& arm, const Eigen::Vector3f& skin_rgb,
                    const MeshDetail& detail = {});

// The head: a capsule (sim::head_shape) turned with pose.head_rotation, its vertices carrying
// their place on the face texture.
void append_head(std::vector<MeshVertex>& mesh, const PersonPose& pose, const Eigen::Vector3f& skin_rgb,
                 const MeshDetail& detail = {});

// The whole user; throws if the pose holds a non-finite point.
std::vector<MeshVertex> person_mesh(const PersonPose& pose, const UserAppearance& user, const MeshDetail& detail = {});

}  // namespace rt::sim
