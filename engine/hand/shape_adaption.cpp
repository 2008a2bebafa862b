#include "hand/shape_adaption.h"

#include <algorithm>
#include <cmath>

namespace rt::hand {
namespace {

constexpr double kMinForearmM = 0.01;  // a shorter forearm measures nothing (as pose_bones has it)

double clamp_scale(double s) { return std::clamp(s, kMinBoneScale, kMaxBoneScale); }

// tracked / reference, 0 when either is missing or not positive.
double ratio(double tracked, double reference) {
  return std::isfinite(tracked) && tracked > 0 && std::isfinite(reference) && reference > 0 ? tracked / reference : 0.0;
}

}  // namespace

BoneScales bone_scales(const HandSkeleton& tracked, const RestSkeleton& template_rest, const TemplateWidths& widths) {
  BoneScales scales;
  const auto segments = bone_segments(tracked);
  auto measured = [&](int bone, double min_length) -> double {
    const BoneSegment& s = segments[bone];
    if (!s.start.allFinite() || !s.end.allFinite() || !(template_rest[bone].length_m > 1e-4)) return 0.0;
    const double length = (s.end - s.start).norm();
    return length > min_length ? length / template_rest[bone].length_m : 0.0;
  };
  const double wrist = measured(kWristBone, 1e-4);
  if (!(wrist > 0)) {
    scales.error = "the wrist or the middle knuckle is missing: no palm length to adapt to";
    return scales;
  }
  scales.scale[kWristBone] = clamp_scale(wrist);
  for (int bone = 2; bone < kBoneCount; ++bone) {
    const double s = measured(bone, 1e-4);
    scales.scale[bone] = s > 0 ? clamp_scale(s) : scales.scale[bone_parent(bone)];
  }
  const double arm = measured(kArmBone, kMinForearmM);
  scales.scale[kArmBone] = arm > 0 ? clamp_scale(arm) : scales.scale[kWristBone];

  const double palm_width = ratio(tracked.palm_width_m, widths.palm_m);
  for (int bone = kWristBone; bone < kBoneCount; ++bone)
    scales.across[bone] = palm_width > 0 ? clamp_scale(palm_width) : scales.scale[bone];
  const double arm_width = ratio(tracked.arm_width_m, widths.arm_m);
  scales.across[kArmBone] = arm_width > 0    ? clamp_scale(arm_width)
                            : palm_width > 0 ? clamp_scale(palm_width)
                                             : scales.scale[kWristBone];
  return scales;
}

bool forearm_tracked(const HandSkeleton& tracked, const RestSkeleton& template_rest) {
  if (!tracked.has_elbow() || !tracked.wrist.allFinite() || !(template_rest[kArmBone].length_m > 0)) return false;
  const double ratio = (tracked.wrist - tracked.elbow).norm() / template_rest[kArmBone].length_m;
  return ratio >= kMinBoneScale && ratio <= kMaxBoneScale;
}

RestSkeleton adapted_rest_skeleton(const RestSkeleton& template_rest, const BoneScales& scales) {
  RestSkeleton adapted = template_rest;
  for (int bone = 0; bone < kBoneCount; ++bone) adapted[bone].length_m = template_rest[bone].length_m * scales.scale[bone];
  // The wrist stays; the arm ends at it; every other bone starts where its parent's S puts it.
  adapted[kArmBone].frame.translation() =
      adapted[kWristBone].frame.translation() -
      adapted[kArmBone].frame.linear() * Eigen::Vector3d(0, adapted[kArmBone].length_m, 0);
  for (int bone = 2; bone < kBoneCount; ++bone) {
    const int parent = bone_parent(bone);
    const Eigen::Vector3d in_parent = template_rest[parent].frame.inverse() * template_rest[bone].frame.translation();
    adapted[bone].frame.translation() = adapted[parent].frame * Eigen::Vector3d(scales.axes(parent).cwiseProduct(in_parent));
  }
  return adapted;
}

std::array<Eigen::Matrix4d, kBoneCount> shape_matrices(const RestSkeleton& template_rest, const RestSkeleton& adapted,
                                                       const BoneScales& scales) {
  std::array<Eigen::Matrix4d, kBoneCount> matrices;
  for (int bone = 0; bone < kBoneCount; ++bone) {
    Eigen::Matrix4d s = Eigen::Matrix4d::Identity();
    s.topLeftCorner<3, 3>() = scales.axes(bone).asDiagonal();
    matrices[bone] = adapted[bone].frame.matrix() * s * template_rest[bone].frame.inverse().matrix();
  }
  return matrices;
}

namespace {

// Eq. 2's blended matrix for one vertex; the mesh and its positions alone share it, so that both
// give the same positions.
Eigen::Matrix4d blended_shape(const HandVertex& v, const std::array<Eigen::Matrix4d, kBoneCount>& matrices) {
  Eigen::Matrix4d blended = Eigen::Matrix4d::Zero();
  for (int k = 0; k < 4; ++k)
    if (v.weights[k] > 0) blended += double(v.weights[k]) * matrices[size_t(std::clamp(int(v.joints[k]), 0, kBoneCount - 1))];
  return blended;
}

void set_shaped_position(HandVertex& v, const Eigen::Matrix4d& blended) {
  const Eigen::Vector4d p = blended * Eigen::Vector4d(v.position_u[0], v.position_u[1], v.position_u[2], 1.0);
  for (int c = 0; c < 3; ++c) v.position_u[c] = float(p[c]);
}

}  // namespace

std::vector<HandVertex> adapt_rest_mesh(std::span<const HandVertex> template_vertices, const RestSkeleton& template_rest,
                                        const RestSkeleton& adapted, const BoneScales& scales) {
  const auto matrices = shape_matrices(template_rest, adapted, scales);
  std::vector<HandVertex> out(template_vertices.begin(), template_vertices.end());
  for (HandVertex& v : out) {
    const Eigen::Matrix4d blended = blended_shape(v, matrices);
    set_shaped_position(v, blended);
    // Each term's linear part is R_j S_j R_j^T with S_j > 0, so the blend is symmetric positive
    // definite and invertible; the check guards against weights that are all zero.
    const Eigen::Matrix3d linear = blended.topLeftCorner<3, 3>();
    if (!(std::abs(linear.determinant()) > 1e-12)) continue;
    const Eigen::Vector3d n = linear.inverse().transpose() * Eigen::Vector3d(v.normal_v[0], v.normal_v[1], v.normal_v[2]);
    if (!n.allFinite() || !(n.norm() > 1e-12)) continue;
    const Eigen::Vector3d unit = n.normalized();
    for (int c = 0; c < 3; ++c) v.normal_v[c] = float(unit[c]);
  }
  return out;
}

std::vector<HandVertex> adapt_rest_positions(std::span<const HandVertex> template_vertices,
                                             const RestSkeleton& template_rest, const RestSkeleton& adapted,
                                             const BoneScales& scales) {
  const auto matrices = shape_matrices(template_rest, adapted, scales);
  std::vector<HandVertex> out(template_vertices.begin(), template_vertices.end());
  for (HandVertex& v : out) set_shaped_position(v, blended_shape(v, matrices));
  return out;
}

}  // namespace rt::hand
