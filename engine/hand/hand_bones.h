#pragma once
// The hand template's bones and their frames (paper section 3.1.2). The hierarchy is the
// tracker's: arm (elbow to wrist), wrist (wrist to the middle knuckle: the palm), and per digit
// metacarpal, proximal, intermediate, distal (the thumb's metacarpal has zero length).
//
// A bone's frame has its origin at the bone's first joint, +y along the bone, +x the hand's
// lateral axis (direction x palm normal) made orthogonal to the bone, +z = x cross y (out of
// the palm when the hand is flat). Orientations come from the tracked joints; origins come by
// forward kinematics from the tracked wrist with the mesh's own bone offsets, so that the mesh
// never tears: with the template's lengths the fingertips land where the template's fingers
// end (which shape adaption then fixes).
#include <Eigen/Geometry>

#include <array>
#include <string>

#include "shared/config.h"
#include "tracking/hand_skeleton.h"

namespace rt::hand {

inline constexpr int kBoneCount = RT_HAND_BONES;
inline constexpr int kArmBone = 0;
inline constexpr int kWristBone = 1;
inline constexpr int kBonesPerDigit = 4;
constexpr int digit_bone(int digit, int bone) { return 2 + kBonesPerDigit * digit + bone; }
int bone_parent(int bone);       // -1 for the arm
std::string bone_name(int bone);  // "arm", "wrist", "thumb_metacarpal", "index_distal", ...

struct BoneRest {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  // B_j: template frame <- bone frame
  double length_m = 0.0;
};
using RestSkeleton = std::array<BoneRest, kBoneCount>;
using BoneFrames = std::array<Eigen::Isometry3d, kBoneCount>;

// First and last joint of each bone of a tracked hand.
struct BoneSegment {
  Eigen::Vector3d start, end;
};
std::array<BoneSegment, kBoneCount> bone_segments(const HandSkeleton& hand);

// The rest skeleton of a complete skeleton: frames by the rule above with origins at the
// joints. Throws std::invalid_argument if a joint is missing or the hand frame is degenerate.
RestSkeleton rest_skeleton_from(const HandSkeleton& hand);

// A posed hand: F_j per bone, in the tracked skeleton's frame (the site frame).
struct BonePose {
  BoneFrames frames{};
  std::string error;  // empty when the pose is usable; otherwise why not (hold the last pose)
  int fallback_bones = 0;  // bones whose joints were missing or degenerate and took the rest pose
  bool ok() const { return error.empty(); }
};
// Robust to a zero-length thumb metacarpal (it takes its next bone's direction), collinear
// joints (the lateral axis comes from the palm, not from neighbouring joints), and missing
// (non-finite) joints: a bone without its joints keeps its rest orientation relative to its
// parent. Fails only without a wrist position or any way to form the hand's frame.
BonePose pose_bones(const HandSkeleton& tracked, const RestSkeleton& rest);

// T_j = F_j B_j^-1 (paper Eq. 1), as column-major float matrices for the skinning pass.
std::array<std::array<float, 16>, kBoneCount> skinning_matrices(const BoneFrames& pose, const RestSkeleton& rest);
Eigen::Matrix4d skinning_transform(const Eigen::Isometry3d& pose, const BoneRest& rest);

// Where a digit's tip joint lands: the end of its distal bone in the pose.
Eigen::Vector3d posed_tip(const BoneFrames& pose, const RestSkeleton& rest, int digit);

}  // namespace rt::hand
