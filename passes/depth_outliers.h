#pragma once
// Pass: a depth camera's flying pixels and lone outliers removed (shaders/depth_outliers.comp).
//   in:  depth_mm r16ui (millimetres, 0 = no measurement)
//   out: filtered_mm r16ui, the same size: each pixel as measured where enough of its eight
//        neighbours lie on its surface, 0 (no measurement) where too few do
// A real time-of-flight camera's depth goes through it before registration and fusion
// (pipeline/recorded_depth_registration.h); the simulator's depth has no flying pixels.
#include <string>

#include "image/host_image.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct DepthOutliersSettings {
  // Neighbours on one surface differ by less than this (or the relative step times the depth).
  // An Azure Kinect pixel (about 1.7 mrad NFOV unbinned, 3.4 binned) on a surface at 70 degrees
  // to the view steps 5-10 mm at 1 m, and its noise is up to 17 mm; a flying pixel sits
  // anywhere between a person and the wall, typically tens of centimetres from both.
  float max_step_mm = 30.0f;
  float max_step_relative = 0.03f;
  // Neighbours (of eight) that must agree: three keeps a surface's convex corner and drops a
  // line of flying pixels along an edge, which has two.
  int min_support = 3;
};

class DepthOutliersPass {
 public:
  // Throws std::invalid_argument for steps that are negative or not finite, or min_support
  // outside 0..8.
  DepthOutliersPass(vk::Context& context, const DepthOutliersSettings& settings = {});
  void add_to(vk::FrameGraph& graph, vk::Image& depth_mm, vk::Image& filtered_mm,
              const std::string& pass_name = "depth_outliers") const;

 private:
  vk::ComputeKernel kernel_;
};

// The plain C++ reference on an R16U image (texels as vk::upload stores them: NaN 0, clamped to
// 0..65535, rounded). Returns R16U of the same size.
HostImage depth_outliers_reference(const HostImage& depth_mm, const DepthOutliersSettings& settings = {});

}  // namespace rt::passes
