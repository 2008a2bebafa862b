#include "hand/hand_bones.h"

#include <cmath>
#include <optional>
#include <stdexcept>

namespace rt::hand {
namespace {

constexpr double kMinBoneM = 1e-5;  // shorter bones have no direction of their own

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

std::optional<Eigen::Vector3d> unit(const Eigen::Vector3d& v, double min_norm = 1e-9) {
  if (!finite(v) || !(v.norm() > min_norm)) return std::nullopt;
  return v.normalized();
}

std::optional<Eigen::Vector3d> direction_of(const BoneSegment& segment) {
  if (!finite(segment.start) || !finite(segment.end)) return std::nullopt;
  return unit(segment.end - segment.start, kMinBoneM);
}

// The rotation with +y = `along` and +x as close to `lateral` as possible; falls back to +z as
// close to `normal` when the bone runs along the lateral axis.
Eigen::Matrix3d bone_rotation(const Eigen::Vector3d& along, const Eigen::Vector3d& lateral, const Eigen::Vector3d& normal) {
  Eigen::Vector3d x = lateral - along * along.dot(lateral);
  Eigen::Vector3d z;
  if (x.norm() > 0.1) {
    x.normalize();
    z = x.cross(along);
  } else {
    z = normal - along * along.dot(normal);
    if (z.norm() < 1e-6) z = along.unitOrthogonal();
    z.normalize();
    x = along.cross(z);
  }
  Eigen::Matrix3d rotation;
  rotation << x, along, z;
  return rotation;
}

// The wrist bone's rotation: +y along the hand's direction, +z the palm normal.
std::optional<Eigen::Matrix3d> hand_rotation(const HandSkeleton& hand) {
  std::optional<Eigen::Vector3d> along = unit(hand.direction);
  if (!along) along = unit(hand.joint(Digit::Middle, DigitJoint::Mcp) - hand.wrist);
  if (!along) return std::nullopt;
  Eigen::Vector3d normal = finite(hand.palm_normal) ? Eigen::Vector3d(hand.palm_normal - *along * along->dot(hand.palm_normal))
                                                     : Eigen::Vector3d::Zero();
  if (normal.norm() < 1e-3) {
    // From the knuckles: index x pinky (from the wrist) points out of a right palm.
    const Eigen::Vector3d index = hand.joint(Digit::Index, DigitJoint::Mcp) - hand.wrist;
    const Eigen::Vector3d pinky = hand.joint(Digit::Pinky, DigitJoint::Mcp) - hand.wrist;
    normal = (hand.is_left ? -1.0 : 1.0) * index.cross(pinky);
    if (!finite(normal)) return std::nullopt;
    normal -= *along * along->dot(normal);
    if (normal.norm() < 1e-9) return std::nullopt;
  }
  normal.normalize();
  Eigen::Matrix3d rotation;
  rotation << along->cross(normal), *along, normal;
  return rotation;
}

}  // namespace

int bone_parent(int bone) {
  if (bone <= kArmBone) return -1;
  if (bone == kWristBone) return kArmBone;
  return (bone - 2) % kBonesPerDigit == 0 ? kWristBone : bone - 1;
}

std::string bone_name(int bone) {
  static const char* digits[] = {"thumb", "index", "middle", "ring", "pinky"};
  static const char* bones[] = {"metacarpal", "proximal", "intermediate", "distal"};
  if (bone == kArmBone) return "arm";
  if (bone == kWristBone) return "wrist";
  if (bone < 0 || bone >= kBoneCount) return "bone" + std::to_string(bone);
  return std::string(digits[(bone - 2) / kBonesPerDigit]) + "_" + bones[(bone - 2) % kBonesPerDigit];
}

std::array<BoneSegment, kBoneCount> bone_segments(const HandSkeleton& hand) {
  std::array<BoneSegment, kBoneCount> segments;
  segments[kArmBone] = {hand.elbow, hand.wrist};
  segments[kWristBone] = {hand.wrist, hand.joint(Digit::Middle, DigitJoint::Mcp)};
  for (int d = 0; d < kDigitCount; ++d)
    for (int b = 0; b < kBonesPerDigit; ++b) segments[digit_bone(d, b)] = {hand.digits[d][b], hand.digits[d][b + 1]};
  return segments;
}

namespace {

// Orientations of every bone; nullopt where the joints give none (the caller decides).
std::array<std::optional<Eigen::Matrix3d>, kBoneCount> bone_rotations(const HandSkeleton& hand) {
  std::array<std::optional<Eigen::Matrix3d>, kBoneCount> rotations;
  const std::optional<Eigen::Matrix3d> palm = hand_rotation(hand);
  if (!palm) return rotations;
  rotations[kWristBone] = palm;
  const Eigen::Vector3d lateral = palm->col(0), normal = palm->col(2);
  const auto segments = bone_segments(hand);
  // The forearm usually continues the hand; an elbow closer than 1 cm gives no direction.
  std::optional<Eigen::Vector3d> arm = finite(hand.elbow) ? unit(hand.wrist - hand.elbow, 0.01) : std::nullopt;
  rotations[kArmBone] = bone_rotation(arm ? *arm : palm->col(1), lateral, normal);
  for (int d = 0; d < kDigitCount; ++d)
    for (int b = 0; b < kBonesPerDigit; ++b) {
      std::optional<Eigen::Vector3d> along = direction_of(segments[digit_bone(d, b)]);
      // A zero-length bone (the thumb's metacarpal) points where the digit goes on.
      for (int next = b + 1; !along && next < kBonesPerDigit && finite(segments[digit_bone(d, b)].start) &&
                             (segments[digit_bone(d, b)].end - segments[digit_bone(d, b)].start).norm() <= kMinBoneM;
           ++next)
        along = direction_of(segments[digit_bone(d, next)]);
      if (along) rotations[digit_bone(d, b)] = bone_rotation(*along, lateral, normal);
    }
  return rotations;
}

}  // namespace

RestSkeleton rest_skeleton_from(const HandSkeleton& hand) {
  const auto rotations = bone_rotations(hand);
  const auto segments = bone_segments(hand);
  RestSkeleton rest;
  for (int bone = 0; bone < kBoneCount; ++bone) {
    if (!rotations[bone] || !finite(segments[bone].start) || !finite(segments[bone].end))
      throw std::invalid_argument("rest skeleton: bone " + bone_name(bone) + " has no usable joints");
    rest[bone].frame.linear() = *rotations[bone];
    rest[bone].frame.translation() = segments[bone].start;
    rest[bone].length_m = (segments[bone].end - segments[bone].start).norm();
  }
  return rest;
}

BonePose pose_bones(const HandSkeleton& tracked, const RestSkeleton& rest) {
  BonePose pose;
  if (!finite(tracked.wrist)) {
    pose.error = "the wrist position is missing";
    return pose;
  }
  const auto rotations = bone_rotations(tracked);
  if (!rotations[kWristBone]) {
    pose.error = "no hand frame: the direction, the palm normal and the knuckles are all missing or degenerate";
    return pose;
  }
  Eigen::Matrix3d rotation[kBoneCount];
  for (int bone = 0; bone < kBoneCount; ++bone) {
    if (rotations[bone]) {
      rotation[bone] = *rotations[bone];
    } else {
      // Parents come first in bone order: keep the rest pose relative to the parent.
      const int parent = bone_parent(bone);
      rotation[bone] = rotation[parent] * rest[parent].frame.linear().transpose() * rest[bone].frame.linear();
      ++pose.fallback_bones;
    }
  }
  // Forward kinematics from the wrist, with the mesh's offsets of each bone in its parent.
  pose.frames[kWristBone].linear() = rotation[kWristBone];
  pose.frames[kWristBone].translation() = tracked.wrist;
  pose.frames[kArmBone].linear() = rotation[kArmBone];
  pose.frames[kArmBone].translation() = tracked.wrist - rotation[kArmBone] * Eigen::Vector3d(0, rest[kArmBone].length_m, 0);
  for (int bone = 2; bone < kBoneCount; ++bone) {
    const int parent = bone_parent(bone);
    const Eigen::Vector3d offset = rest[parent].frame.inverse() * rest[bone].frame.translation();
    pose.frames[bone].linear() = rotation[bone];
    pose.frames[bone].translation() = pose.frames[parent] * offset;
  }
  for (int bone = 0; bone < kBoneCount; ++bone)
    if (!pose.frames[bone].matrix().allFinite()) {
      pose.error = "bone " + bone_name(bone) + " came out non-finite";
      return pose;
    }
  return pose;
}

Eigen::Matrix4d skinning_transform(const Eigen::Isometry3d& pose, const BoneRest& rest) {
  return (pose * rest.frame.inverse()).matrix();
}

std::array<std::array<float, 16>, kBoneCount> skinning_matrices(const BoneFrames& pose, const RestSkeleton& rest) {
  std::array<std::array<float, 16>, kBoneCount> matrices;
  for (int bone = 0; bone < kBoneCount; ++bone) {
    const Eigen::Matrix4d t = skinning_transform(pose[bone], rest[bone]);
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) matrices[bone][column * 4 + row] = float(t(row, column));
  }
  return matrices;
}

Eigen::Vector3d posed_tip(const BoneFrames& pose, const RestSkeleton& rest, int digit) {
  const int distal = digit_bone(digit, 3);
  return pose[distal] * Eigen::Vector3d(0, rest[distal].length_m, 0);
}

}  // namespace rt::hand
