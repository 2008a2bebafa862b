#pragma once
// Pass: linear blend skinning of the hand template (paper Eq. 1), one invocation per vertex.
//   in:  rest (HandVertex[]), bones (RT_HAND_BONES column-major mat4 T_j = F_j B_j^-1)
//   out: skinned (SkinnedVertex[]: site-frame position and normal, texture coordinates)
#include <array>
#include <functional>
#include <span>
#include <vector>

#include "shared/config.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

using shader_abi::HandVertex;
using shader_abi::SkinnedVertex;
using BoneMatrices = std::array<std::array<float, 16>, RT_HAND_BONES>;

class HandSkinningPass {
 public:
  explicit HandSkinningPass(vk::Context& context);
  // `vertex_count` is read when each frame is recorded; the buffers must hold that many.
  void add_to(vk::FrameGraph& graph, vk::Buffer& rest, vk::Buffer& bones, vk::Buffer& skinned,
              std::function<uint32_t()> vertex_count, const std::string& pass_name = "hand_skinning") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference, in double precision: hand::skin_vertices (hand/skinning.h), which the
// touch detector skins its hands with too.
std::vector<SkinnedVertex> hand_skinning_reference(std::span<const HandVertex> rest, const BoneMatrices& bones);

}  // namespace rt::passes
