#pragma once
// The sender's image-based model (paper 3.1.1) as one frame graph: background removal, depth
// reprojection with min (or average) fusion and crack filling, optional see-through carving and
// plane-sweep refinement, then either warping and unstructured lumigraph blending in one pass,
// or warping of each selected view and blending by lumigraph weights or by Lumi-Net
// (settings.blending, settings.split_warp), then optional resolving of a supersampled portrait
// and filling of its enclosed holes. In: the
// site's RGBD images and the target view of the remote eye; out: the portrait (RGBA, straight
// alpha) and its depth.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pipeline/ibr_settings.h"
#include "pipeline/lumi_net.h"
#include "passes/ibr_blend.h"
#include "passes/ibr_carve.h"
#include "passes/ibr_fill.h"
#include "passes/ibr_foreground.h"
#include "passes/ibr_fuse.h"
#include "passes/ibr_refine.h"
#include "passes/ibr_resolve.h"
#include "passes/common/ibr_scene.h"
#include "passes/ibr_splat.h"
#include "passes/ibr_warp.h"
#include "passes/ibr_warp_blend.h"
#include "sim/rgbd_source.h"

namespace rt::pipeline {

class IbrRenderer {
 public:
  // `cameras`: all of the site's cameras (color and depth calibration); each frame uses
  // `settings.views` of them. All color images must share one size, all depth images too.
  IbrRenderer(vk::Context& context, std::vector<passes::IbrCameraModel> cameras, const IbrSettings& settings);
  ~IbrRenderer();

  // Renders one frame: `selection` indexes `cameras` (settings.views of them), `images` holds
  // every camera's image of this frame, in the order of `cameras`. The target view must be
  // settings.width x settings.height. `prepare` uploads; running graph() renders (a session may
  // capture that run); `render` does both.
  void prepare(std::span<const sim::RgbdImage> images, std::span<const size_t> selection, const Camera& target_view);
  void render(std::span<const sim::RgbdImage> images, std::span<const size_t> selection, const Camera& target_view) {
    prepare(images, selection, target_view);
    graph_->run();
  }

  vk::Image& portrait() { return *portrait_; }
  // The portrait before its holes are filled: what the blending (and resolve) wrote, for a peer
  // that blends alone. The portrait itself when hole filling is off.
  vk::Image& portrait_before_fill() { return unfilled_portrait_ ? *unfilled_portrait_ : *portrait_; }
  vk::Image& portrait_depth() { return *portrait_depth_; }
  vk::FrameGraph& graph() { return *graph_; }
  const IbrSettings& settings() const { return settings_; }
  // What the warp reads in the prepared frame (after the graph ran), for a peer to start from the
  // same surface: the scene table, the depth it warps through, the colour and points atlases.
  struct WarpInputs {
    const passes::IbrSceneTable& table;
    vk::Image& depth;
    vk::Image& color;
    vk::Image& points;
  };
  WarpInputs warp_inputs();
  // With settings.blending Lumi, the network (its tensors, for benchmarks and checks); else null.
  LumiNetBlender* lumi_net() { return lumi_.get(); }
  const LumiNetBlender* lumi_net() const { return lumi_.get(); }

 private:
  struct Images;
  vk::Context& context_;
  std::vector<passes::IbrCameraModel> cameras_;
  IbrSettings settings_;
  passes::IbrForegroundPass foreground_;
  passes::IbrSplatPass splat_;
  passes::IbrFusePass fuse_;
  std::unique_ptr<passes::IbrCarvePass> carve_;
  std::unique_ptr<passes::IbrRefinePass> refine_;
  // Split: warp_ and one of blend_ and lumi_, as settings.blending says; else tiles_ and warp_blend_.
  std::unique_ptr<passes::IbrWarpPass> warp_;
  std::unique_ptr<passes::IbrBlendPass> blend_;
  std::unique_ptr<LumiNetBlender> lumi_;
  std::unique_ptr<passes::IbrTilesPass> tiles_;
  std::unique_ptr<passes::IbrWarpBlendPass> warp_blend_;
  std::unique_ptr<passes::IbrResolvePass> resolve_;
  std::unique_ptr<passes::IbrFillPass> fill_;
  // With hole filling where the warp lists no tiles of the portrait (split, supersampled).
  std::unique_ptr<passes::IbrTilesPass> fill_tiling_;
  std::unique_ptr<passes::IbrTiles> fill_tiles_;
  passes::IbrSceneBuffer scene_;
  passes::IbrSceneTable table_;
  vk::Image* warp_depth_ = nullptr;  // the fused, carved or refined depth, as the settings say
  std::unique_ptr<Images> images_;
  std::unique_ptr<vk::Image> portrait_, portrait_depth_;
  std::unique_ptr<vk::Image> fine_portrait_, fine_portrait_depth_;  // with supersampling
  std::unique_ptr<vk::Image> unfilled_portrait_;                     // with hole filling
  std::unique_ptr<vk::FrameGraph> graph_;
  std::vector<size_t> uploaded_selection_;  // whose depth rays the ray atlas holds
};

// The blending that `renderer` runs, for a command's first lines: "ulr (k = 3)" or "lumi (FILE,
// C = 16, 2 blocks, at 1/2)".
std::string blending_description(const IbrRenderer& renderer);

}  // namespace rt::pipeline
