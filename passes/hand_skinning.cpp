#include "passes/hand_skinning.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

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
  std::vector<SkinnedVertex> out;
  out.reserve(rest.size());
  for (const HandVertex& v : rest) {
    Eigen::Matrix4d blended = Eigen::Matrix4d::Zero();
    for (int k = 0; k < 4; ++k) {
      const int bone = std::clamp(int(v.joints[k] + 0.5f), 0, RT_HAND_BONES - 1);
      blended += double(v.weights[k]) * Eigen::Map<const Eigen::Matrix4f>(bones[size_t(bone)].data()).cast<double>();
    }
    const Eigen::Vector4d p = blended * Eigen::Vector4d(v.position_u[0], v.position_u[1], v.position_u[2], 1.0);
    Eigen::Vector3d n = blended.topLeftCorner<3, 3>() * Eigen::Vector3d(v.normal_v[0], v.normal_v[1], v.normal_v[2]);
    if (n.squaredNorm() > 1e-20) n.normalize();
    else n = Eigen::Vector3d(v.normal_v[0], v.normal_v[1], v.normal_v[2]);
    SkinnedVertex s{};
    s.position_u = {float(p.x()), float(p.y()), float(p.z()), v.position_u[3]};
    s.normal_v = {float(n.x()), float(n.y()), float(n.z()), v.normal_v[3]};
    out.push_back(s);
  }
  return out;
}

}  // namespace rt::passes
