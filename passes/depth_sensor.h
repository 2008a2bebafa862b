#pragma once
// Pass: a time-of-flight depth camera from rendered linear depth (DESIGN.md section 6: Azure
// Kinect depth in millimetres, 0 = invalid).
//   in:  depth_m r32f (camera z in metres, 0 = no surface), part r32f (RT_PART_*)
//   out: depth_mm r16ui (millimetres, 0 = invalid)
// Effects, each off unless set: depth noise with sigma growing as z^2, a skin depth bias,
// dropped and flying pixels at depth edges, a near-range cutoff, depth/color misregistration.
// The noise is a hash of (pixel, seed): reproducible, and the same in the C++ reference.
#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct DepthSensorModel {
  float range_min_m = 0.25f;  // raise it for the near_cutoff effect
  float range_max_m = 2.88f;  // the range of the Azure Kinect, WFOV 2x2 binned
  float noise_sigma_at_1m_m = 0.0f;
  float skin_bias_m = 0.0f;
  float flying_edge_m = 0.0f;  // a neighbour this much farther or nearer makes an edge; 0 = off
  float flying_probability = 0.0f;
  int shift_x = 0, shift_y = 0;  // misregistration, pixels
};

// Throws with the reason for a model that cannot be simulated (negative sigma, empty range...).
void check_depth_sensor_model(const DepthSensorModel& model);

class DepthSensorPass {
 public:
  DepthSensorPass(vk::Context& context, const DepthSensorModel& model);
  void add_to(vk::FrameGraph& graph, vk::Image& depth_m, vk::Image& part, vk::Image& depth_mm,
              std::function<uint32_t()> seed, const std::string& pass_name = "depth_sensor") const;

 private:
  vk::ComputeKernel kernel_;
};

HostImage depth_sensor_reference(const HostImage& depth_m, const HostImage& part, const DepthSensorModel& model,
                                 uint32_t seed);

}  // namespace rt::passes
