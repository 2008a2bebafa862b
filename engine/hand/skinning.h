#pragma once
// Linear blend skinning of the hand template on the CPU (paper Eq. 1), in double precision: the
// reference the GPU skinning pass is tested against (passes/hand_skinning.h), and the skin the
// touch detector finds on the glass (touch/mesh_contact.h).
#include <array>
#include <span>
#include <vector>

#include "hand/hand_bones.h"

namespace rt::hand {

using shader_abi::HandVertex;
using shader_abi::SkinnedVertex;
// T_j per bone, column-major, as skinning_matrices() gives them.
using SkinningMatrices = std::array<std::array<float, 16>, kBoneCount>;

// Positions and normals in the bones' space (the site frame for a tracked pose); texture
// coordinates carried through. A bone index out of range is clamped, a normal the blend
// collapses keeps its rest direction.
std::vector<SkinnedVertex> skin_vertices(std::span<const HandVertex> rest, const SkinningMatrices& bones);
// The positions alone (as skin_vertices gives them), for those who need only where the skin is.
std::vector<std::array<float, 4>> skin_positions(std::span<const HandVertex> rest, const SkinningMatrices& bones);

}  // namespace rt::hand
