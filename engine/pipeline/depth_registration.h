#pragma once
// One k4a-style camera's depth registered into its colour image on the GPU
// (passes/depth_in_color.h), for commands and the sender: the pass with its own frame graph,
// images and buffers, sized once for the camera pair.
#include <Eigen/Geometry>

#include <optional>
#include <vector>

#include "geometry/camera.h"
#include "image/host_image.h"
#include "passes/depth_in_color.h"
#include "passes/depth_outliers.h"
#include "vulkan/frame_graph.h"

namespace rt::pipeline {

class DepthRegistration {
 public:
  // Throws std::invalid_argument for a camera pair the pass cannot take (depth_in_color_params).
  // With `outliers`, the depth's flying pixels and lone outliers are removed first
  // (passes/depth_outliers.h): a real time-of-flight camera's.
  DepthRegistration(vk::Context& context, const CameraIntrinsics& depth, const CameraIntrinsics& color,
                    const Eigen::Isometry3d& color_from_depth, const passes::DepthInColorSettings& settings = {},
                    const std::optional<passes::DepthOutliersSettings>& outliers = std::nullopt);

  // depth_mm: R16U at the depth camera's size (0 = no measurement). Returns R16U at the colour
  // camera's size: millimetres along its z, nearest surface, 0 where none.
  HostImage run(const HostImage& depth_mm);
  // The pass's GPU time per run (its clear, splat and resolve together), median over the runs so
  // far, from the frame graph's timestamps; 0 before a run or without timestamps.
  double median_ms() const;
  // Each of its graph passes' times (clear, splat, resolve), to see which one limits it.
  std::vector<vk::PassTiming> timings() const { return graph_.timings(); }

 private:
  vk::Context& context_;
  passes::DepthInColorPass pass_;  // before the graph: its kernels outlive it
  std::optional<passes::DepthOutliersPass> outliers_;
  vk::Image depth_, filtered_, registered_;
  vk::Buffer rays_, nearest_;
  shader_abi::DepthInColorParams params_;
  vk::FrameGraph graph_;
};

}  // namespace rt::pipeline
