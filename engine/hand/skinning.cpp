#include "hand/skinning.h"

#include <Eigen/Core>
#include <algorithm>

namespace rt::hand {
namespace {

// One vertex's blend of its bones' matrices; the full skinning and the positions alone share it.
Eigen::Matrix4d blended_bones(const HandVertex& v, const SkinningMatrices& bones) {
  Eigen::Matrix4d blended = Eigen::Matrix4d::Zero();
  for (int k = 0; k < 4; ++k) {
    const int bone = std::clamp(int(v.joints[k] + 0.5f), 0, kBoneCount - 1);
    blended += double(v.weights[k]) * Eigen::Map<const Eigen::Matrix4f>(bones[size_t(bone)].data()).cast<double>();
  }
  return blended;
}

std::array<float, 4> skinned_position(const HandVertex& v, const Eigen::Matrix4d& blended) {
  const Eigen::Vector4d p = blended * Eigen::Vector4d(v.position_u[0], v.position_u[1], v.position_u[2], 1.0);
  return {float(p.x()), float(p.y()), float(p.z()), v.position_u[3]};
}

}  // namespace

std::vector<SkinnedVertex> skin_vertices(std::span<const HandVertex> rest, const SkinningMatrices& bones) {
  std::vector<SkinnedVertex> out;
  out.reserve(rest.size());
  for (const HandVertex& v : rest) {
    const Eigen::Matrix4d blended = blended_bones(v, bones);
    Eigen::Vector3d n = blended.topLeftCorner<3, 3>() * Eigen::Vector3d(v.normal_v[0], v.normal_v[1], v.normal_v[2]);
    if (n.squaredNorm() > 1e-20) n.normalize();
    else n = Eigen::Vector3d(v.normal_v[0], v.normal_v[1], v.normal_v[2]);
    SkinnedVertex s{};
    s.position_u = skinned_position(v, blended);
    s.normal_v = {float(n.x()), float(n.y()), float(n.z()), v.normal_v[3]};
    out.push_back(s);
  }
  return out;
}

std::vector<std::array<float, 4>> skin_positions(std::span<const HandVertex> rest, const SkinningMatrices& bones) {
  std::vector<std::array<float, 4>> out;
  out.reserve(rest.size());
  for (const HandVertex& v : rest) out.push_back(skinned_position(v, blended_bones(v, bones)));
  return out;
}

}  // namespace rt::hand
