#pragma once
// The image-based model's warp and lumigraph blend written for the CPU with OpenCV, for
// `bench ibr` to compare the GPU passes with the figure a user would compare them with: the same
// inputs as ibr_warp (the fused depth, the views' 8-bit colour, their own depths, the camera
// table), the same visibility test and penalties, cv::remap for the sampling and whole-image
// OpenCV arithmetic for the weights, on OpenCV's threads.
#include <opencv2/core.hpp>
#include <vector>

#include "image/host_image.h"
#include "passes/common/ibr_scene.h"
#include "passes/ibr_blend.h"
#include "passes/ibr_warp.h"

namespace rt::pipeline {

// The peer's inputs in the form a CPU implementation holds them (not timed: converting them from
// the GPU's atlases is the benchmark's business, not the peer's work).
struct IbrCpuPeerInputs {
  passes::IbrSceneTable table;
  cv::Mat fused_depth;             // CV_32F, target-sized, 0 = nothing
  std::vector<cv::Mat> colors;     // CV_8UC4 per view, the camera's colour image
  std::vector<cv::Mat> own_depth;  // CV_32F per view, the view's own depth in its depth pixels, 0 = none
};

// From the atlases ibr_warp reads (views in bands).
IbrCpuPeerInputs cpu_peer_inputs(const passes::IbrSceneTable& table, const HostImage& fused_depth,
                                 const HostImage& color_atlas, const HostImage& points_atlas);

struct IbrCpuPeerTimes {
  double maps_ms = 0;    // per view: the projections, the visibility test, penalties and feather
  double sample_ms = 0;  // cv::remap of colour and own depth
  double blend_ms = 0;   // the lumigraph weights and the weighted sum
  double total() const { return maps_ms + sample_ms + blend_ms; }
};

struct IbrCpuPeerResult {
  cv::Mat portrait;  // CV_32FC4: straight rgb in [0, 1], alpha 1 where a view sees the point
  IbrCpuPeerTimes times;
};

IbrCpuPeerResult run_ibr_cpu_peer(const IbrCpuPeerInputs& inputs, const passes::WarpSettings& warp,
                                  const passes::BlendSettings& blend);

}  // namespace rt::pipeline
