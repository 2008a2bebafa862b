#pragma once
// Shape adaption (paper Eq. 2): V'_i = sum_j w_ji B'_j S_j B_j^-1 V_i. The paper's S_j is a
// uniform scale by the bone's length ratio; here S_j = diag(across, along, across) in the bone's
// frame (+y along the bone): along = tracked length / template length, across = the tracked
// width / the template's width where the tracker measures one (the palm width for the palm and
// the fingers, the arm width for the forearm), else the uniform scale of the paper. The adapted
// rest skeleton B'_j keeps the template's orientations and moves each bone's origin with its
// parent's S, so the adapted rest mesh is the template with every bone resized in place. Done
// once when the hand is first tracked well, and again on request.
#include <array>
#include <limits>
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
  std::array<double, kBoneCount> scale{};   // along the bone (its length ratio)
  std::array<double, kBoneCount> across{};  // across it: the bone frame's x and z
  std::string error;  // empty when usable
  bool ok() const { return error.empty(); }
  Eigen::Vector3d axes(int bone) const { return {across[size_t(bone)], scale[size_t(bone)], across[size_t(bone)]}; }
};

// The template's own widths, to divide the tracked ones by (NaN: fit no width).
struct TemplateWidths {
  double palm_m = std::numeric_limits<double>::quiet_NaN();
  double arm_m = std::numeric_limits<double>::quiet_NaN();
};

// Along: the wrist bone (wrist to middle knuckle) must be measurable; a digit bone that is not
// (missing joints, zero length like the thumb's metacarpal) takes its parent's scale; the arm
// measures |elbow - wrist| and takes the wrist's scale without an elbow or with a forearm shorter
// than 1 cm. Across: with the tracker's palm width, palm width / template palm width for the
// palm and every digit bone; the arm's from the arm width, else that palm ratio; without either
// width a bone's across is its along (the paper's uniform scale). All clamped to
// [kMinBoneScale, kMaxBoneScale].
BoneScales bone_scales(const HandSkeleton& tracked, const RestSkeleton& template_rest, const TemplateWidths& widths = {});

// Whether the skeleton has a forearm to draw: a tracked elbow within [kMinBoneScale,
// kMaxBoneScale] times the template's forearm length from the wrist. A missing elbow, a
// zero-length forearm or a wild one give the hand alone: no forearm is invented.
bool forearm_tracked(const HandSkeleton& tracked, const RestSkeleton& template_rest);

// B'_j and the adapted lengths.
RestSkeleton adapted_rest_skeleton(const RestSkeleton& template_rest, const BoneScales& scales);

// The per-bone matrices B'_j S_j B_j^-1 of Eq. 2.
std::array<Eigen::Matrix4d, kBoneCount> shape_matrices(const RestSkeleton& template_rest, const RestSkeleton& adapted,
                                                       const BoneScales& scales);

// Eq. 2 over the template's rest vertices. Normals go by the inverse transpose of the blended
// linear part (a non-uniform scale turns them), renormalised; a vertex whose blend cannot be
// inverted keeps its normal.
std::vector<HandVertex> adapt_rest_mesh(std::span<const HandVertex> template_vertices, const RestSkeleton& template_rest,
                                        const RestSkeleton& adapted, const BoneScales& scales);
// The same positions without the normals (left as the template's), for those who need only
// where the skin is: the touch detector, every tick.
std::vector<HandVertex> adapt_rest_positions(std::span<const HandVertex> template_vertices,
                                             const RestSkeleton& template_rest, const RestSkeleton& adapted,
                                             const BoneScales& scales);

}  // namespace rt::hand
