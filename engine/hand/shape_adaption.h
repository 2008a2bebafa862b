#pragma once
// Shape adaption (paper Eq. 2): V'_i = sum_j w_ji B'_j S_j B_j^-1 V_i. Each bone gets a uniform
// scale S_j = tracked length / template length; the adapted rest skeleton B'_j keeps the
// template's orientations and moves each bone's origin with its parent's scale, so the adapted
// rest mesh is the template with every bone resized in place. Done once when the hand is first
// tracked well, and again on request.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "hand/hand_bones.h"

namespace rt::hand {

using shader_abi::HandVertex;

// Scales beyond these come from bad tracking, not from hands.
inline constexpr double kMinBoneScale = 0.5;
inline constexpr double kMaxBoneScale = 2.0;

struct BoneScales {
  std::array<double, kBoneCount> scale{};
  std::string error;  // empty when usable
  bool ok() const { return error.empty(); }
};

// The wrist bone (wrist to middle knuckle) must be measurable; a digit bone that is not
// (missing joints, zero length like the thumb's metacarpal) takes its parent's scale; the arm
// takes the wrist's (the mesh holds only the forearm's end, and forearm length says little
// about the hand). Scales are clamped to [kMinBoneScale, kMaxBoneScale].
BoneScales bone_scales(const HandSkeleton& tracked, const RestSkeleton& template_rest);

// B'_j and the adapted lengths.
RestSkeleton adapted_rest_skeleton(const RestSkeleton& template_rest, const BoneScales& scales);

// The per-bone matrices B'_j S_j B_j^-1 of Eq. 2.
std::array<Eigen::Matrix4d, kBoneCount> shape_matrices(const RestSkeleton& template_rest, const RestSkeleton& adapted,
                                                       const BoneScales& scales);

// Eq. 2 over the template's rest vertices (normals keep their direction: each term rotates by
// R'_j R_j^T = I, and a uniform scale does not turn them).
std::vector<HandVertex> adapt_rest_mesh(std::span<const HandVertex> template_vertices, const RestSkeleton& template_rest,
                                        const RestSkeleton& adapted, const BoneScales& scales);

}  // namespace rt::hand
