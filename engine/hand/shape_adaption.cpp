#include "hand/shape_adaption.h"

#include <algorithm>
#include <cmath>

namespace rt::hand {

BoneScales bone_scales(const HandSkeleton& tracked, const RestSkeleton& template_rest) {
  BoneScales scales;
  const auto segments = bone_segments(tracked);
  auto measured = [&](int bone) -> double {
    const BoneSegment& s = segments[bone];
    if (!s.start.allFinite() || !s.end.allFinite() || !(template_rest[bone].length_m > 1e-4)) return 0.0;
    const double length = (s.end - s.start).norm();
    return length > 1e-4 ? length / template_rest[bone].length_m : 0.0;
  };
  const double wrist = measured(kWristBone);
  if (!(wrist > 0)) {
    scales.error = "the wrist or the middle knuckle is missing: no palm length to adapt to";
    return scales;
  }
  scales.scale[kWristBone] = std::clamp(wrist, kMinBoneScale, kMaxBoneScale);
  scales.scale[kArmBone] = scales.scale[kWristBone];
  for (int bone = 2; bone < kBoneCount; ++bone) {
    const double s = measured(bone);
    scales.scale[bone] = s > 0 ? std::clamp(s, kMinBoneScale, kMaxBoneScale) : scales.scale[bone_parent(bone)];
  }
  return scales;
}

RestSkeleton adapted_rest_skeleton(const RestSkeleton& template_rest, const BoneScales& scales) {
  RestSkeleton adapted = template_rest;
  for (int bone = 0; bone < kBoneCount; ++bone) adapted[bone].length_m = template_rest[bone].length_m * scales.scale[bone];
  // The wrist stays; the arm ends at it; every other bone starts where its parent's scale puts it.
  adapted[kArmBone].frame.translation() =
      adapted[kWristBone].frame.translation() -
      adapted[kArmBone].frame.linear() * Eigen::Vector3d(0, adapted[kArmBone].length_m, 0);
  for (int bone = 2; bone < kBoneCount; ++bone) {
    const int parent = bone_parent(bone);
    const Eigen::Vector3d in_parent = template_rest[parent].frame.inverse() * template_rest[bone].frame.translation();
    adapted[bone].frame.translation() = adapted[parent].frame * (scales.scale[parent] * in_parent);
  }
  return adapted;
}

std::array<Eigen::Matrix4d, kBoneCount> shape_matrices(const RestSkeleton& template_rest, const RestSkeleton& adapted,
                                                       const BoneScales& scales) {
  std::array<Eigen::Matrix4d, kBoneCount> matrices;
  for (int bone = 0; bone < kBoneCount; ++bone) {
    Eigen::Matrix4d s = Eigen::Matrix4d::Identity();
    s.topLeftCorner<3, 3>() *= scales.scale[bone];
    matrices[bone] = adapted[bone].frame.matrix() * s * template_rest[bone].frame.inverse().matrix();
  }
  return matrices;
}

std::vector<HandVertex> adapt_rest_mesh(std::span<const HandVertex> template_vertices, const RestSkeleton& template_rest,
                                        const RestSkeleton& adapted, const BoneScales& scales) {
  const auto matrices = shape_matrices(template_rest, adapted, scales);
  std::vector<HandVertex> out(template_vertices.begin(), template_vertices.end());
  for (HandVertex& v : out) {
    const Eigen::Vector4d p(v.position_u[0], v.position_u[1], v.position_u[2], 1.0);
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (int k = 0; k < 4; ++k) {
      if (!(v.weights[k] > 0)) continue;
      sum += double(v.weights[k]) * (matrices[int(v.joints[k])] * p);
    }
    for (int c = 0; c < 3; ++c) v.position_u[c] = float(sum[c]);
  }
  return out;
}

}  // namespace rt::hand
