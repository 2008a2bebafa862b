#pragma once
// Pass: every view's color warped into the target view through the fused depth
// (shaders/ibr_warp.comp).
//   in:  fused_depth r32f, color rgba8 atlas (views in bands), points rgba32f atlas (each view's
//        own depth in w), the camera table
//   out: warped rgba32f atlas (rgb, visible) and features rgba32f atlas (angle penalty in radians,
//        resolution penalty in metres, field-of-view feather, visible), one target-sized band per
//        view: the inputs of a learned blending (the lumigraph blending runs fused with the
//        warp, passes/ibr_warp_blend.h, and needs no atlases).
// A view sees a surface point when it projects inside its color and depth images and its own
// depth there agrees (passes::VisibilityTolerance).
#include "passes/common/ibr_scene.h"
#include "vulkan/frame_graph.h"

namespace rt::passes {

struct WarpSettings {
  VisibilityTolerance visibility;  // refinement uses the same
  float feather_px = 16.0f;
};
// `s`, or std::invalid_argument saying which setting is out of range.
const WarpSettings& checked_warp_settings(const WarpSettings& s);

class IbrWarpPass {
 public:
  IbrWarpPass(vk::Context& context, const WarpSettings& settings = {});
  void add_to(vk::FrameGraph& graph, IbrSceneBuffer& scene, vk::Image& fused_depth, vk::Image& color,
              vk::Image& points, vk::Image& warped, vk::Image& features, uint32_t view_count) const;

 private:
  vk::ComputeKernel kernel_;
};

// How far a frame's view samples get through the warp's tests, as the reference counts them on
// its way, and the floating-point arithmetic that takes: what a benchmark sets against the
// device's arithmetic peak. A sample is a target pixel with a surface and a view.
struct WarpWork {
  uint64_t surface_pixels = 0;  // fused depth > 0
  uint64_t samples = 0;         // surface pixels times views
  uint64_t in_front = 0;        // in front of the view's camera: projected through both lenses
  uint64_t inside = 0;          // inside the colour and depth images: visibility tested
  uint64_t seen = 0;            // visible: colour sampled, angle, resolution and feather computed
  uint64_t covered = 0;         // surface pixels seen by at least one view
  // Adds, multiplies, divisions and square roots count one operation each, a fused multiply-add
  // two, the arc cosine one; comparisons, clamps and integer work none. Work the shader does once
  // per view rather than per sample (the eye's and the camera's centres) is not counted.
  double flops() const;
};

struct WarpedViews {
  HostImage warped;    // rgba32f atlas
  HostImage features;  // rgba32f atlas
};
// With `work`, also counts how far the samples got (the same tests as the shader).
WarpedViews ibr_warp_reference(const IbrSceneTable& table, const HostImage& fused_depth, const HostImage& color,
                               const HostImage& points, const WarpSettings& settings = {}, WarpWork* work = nullptr);

}  // namespace rt::passes
