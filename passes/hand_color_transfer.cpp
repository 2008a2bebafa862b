#include "passes/hand_color_transfer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hand/color_space.h"
#include "hand_color_transfer.comp.h"

namespace rt::passes {

namespace {

float checked_contrast(float max_contrast) {
  if (!(max_contrast > 0.0f) || !std::isfinite(max_contrast))
    throw std::invalid_argument("hand_color_transfer: max_contrast must be a positive number");
  return max_contrast;
}

}  // namespace

HandColorTransferPass::HandColorTransferPass(vk::Context& context, float max_contrast)
    : kernel_(context, "hand_color_transfer", hand_color_transfer_comp_spirv,
              {{"max_contrast", checked_contrast(max_contrast)}}) {}

void HandColorTransferPass::add_to(vk::FrameGraph& graph, vk::Image& template_texture, vk::Buffer& state,
                                   vk::Image& adapted_texture, float sigma_floor, const std::string& pass_name) const {
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"template_texture", &template_texture}, {"adapted_texture", &adapted_texture}, {"State", &state}},
      .threads = {adapted_texture.width(), adapted_texture.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::ColorTransferParams>(
          [sigma_floor] { return shader_abi::ColorTransferParams{sigma_floor}; }),
  });
}

HostImage color_transfer_reference(const HostImage& template_texture, const AppearanceState& state, float sigma_floor,
                                   float max_contrast) {
  HostImage out = template_texture;
  if (!(state.header[0] > 0.5f)) return out;
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(state.image_mean[c]) || !std::isfinite(state.image_sigma[c]) || !std::isfinite(state.mesh_mean[c]) ||
        !std::isfinite(state.mesh_sigma[c]))
      return out;
  const double floor = std::max(double(sigma_floor), 1e-6);
  for (uint32_t y = 0; y < out.height; ++y)
    for (uint32_t x = 0; x < out.width; ++x) {
      Eigen::Vector3d rgb(template_texture.at(x, y, 0), template_texture.at(x, y, 1), template_texture.at(x, y, 2));
      const Eigen::Vector3d lab = hand::rgb_to_lab_alpha_beta(rgb.cwiseMax(0.0).cwiseMin(1.0));
      Eigen::Vector3d adapted;
      for (int c = 0; c < 3; ++c)
        adapted[c] = hand::transfer_channel(lab[c], {state.image_mean[c], state.image_sigma[c]},
                                            {state.mesh_mean[c], state.mesh_sigma[c]}, floor, double(max_contrast));
      const Eigen::Vector3d result = hand::lab_alpha_beta_to_rgb(adapted);
      if (!result.allFinite()) continue;
      for (uint32_t c = 0; c < 3; ++c) out.at(x, y, c) = float(std::clamp(result[c], 0.0, 1.0));
    }
  return out;
}

}  // namespace rt::passes
