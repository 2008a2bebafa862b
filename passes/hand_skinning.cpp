#include "passes/hand_skinning.h"

#include <algorithm>

#include "hand/skinning.h"
#include "hand_skinning.comp.h"

namespace rt::passes {

HandSkinningPass::HandSkinningPass(vk::Context& context) : kernel_(context, "hand_skinning", hand_skinning_comp_spirv) {}

void HandSkinningPass::add_to(vk::FrameGraph& graph, vk::Buffer& rest, vk::Buffer& bones, vk::Buffer& skinned,
                              std::function<uint32_t()> vertex_count, const std::string& pass_name) const {
  // The dispatch covers the buffers' capacity; the shader stops at the frame's vertex count.
  const uint32_t capacity = uint32_t(std::max<VkDeviceSize>(1, rest.size() / sizeof(HandVertex)));
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"RestVertices", &rest}, {"BoneTransforms", &bones}, {"Skinned", &skinned}},
      .threads = {capacity, 1, 1},
      .push_constants = vk::push_constants_from<shader_abi::HandSkinParams>(
          [count = std::move(vertex_count), capacity] { return shader_abi::HandSkinParams{std::min(count(), capacity)}; }),
  });
}

std::vector<SkinnedVertex> hand_skinning_reference(std::span<const HandVertex> rest, const BoneMatrices& bones) {
  return hand::skin_vertices(rest, bones);
}

}  // namespace rt::passes
