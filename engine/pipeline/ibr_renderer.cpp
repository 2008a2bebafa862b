#include "pipeline/ibr_renderer.h"

#include <stdexcept>
#include <string>

namespace rt::pipeline {
namespace {

IbrSettings with_fusion(IbrSettings settings) {
  if (settings.views == 0 || settings.views > RT_IBR_MAX_VIEWS)
    throw std::invalid_argument("image-based model: views must be 1.." + std::to_string(RT_IBR_MAX_VIEWS));
  if (settings.width == 0 || settings.height == 0) throw std::invalid_argument("image-based model: empty target view");
  if (settings.supersample == 0 || settings.supersample > 4)
    throw std::invalid_argument("image-based model: supersample must be 1..4");
  settings.splat.max_footprint_px *= float(settings.supersample);
  settings.splat.fusion = settings.fusion;
  settings.fuse.fusion = settings.fusion;
  return settings;
}

}  // namespace

struct IbrRenderer::Images {
  vk::Image depth_mm, depth_rays, points, color;        // views in bands
  vk::Buffer fusion;
  vk::Image fused_depth, carved_depth, refined_depth;  // target sized
  std::unique_ptr<vk::Image> warped, features;         // the split path's: target sized, views in bands
  passes::IbrTiles point_tiles;                        // of the points atlas, one layer per view
  std::unique_ptr<passes::IbrTiles> tiles;             // the one pass's: the tiles with a surface

  // `s.width` x `s.height` here are the rendered (supersampled) size.
  Images(vk::Context& context, const passes::IbrCameraModel& camera, const IbrSettings& s, bool split)
      : depth_mm(context, {"ibr depth mm", camera.depth.intrinsics.width, camera.depth.intrinsics.height * s.views,
                           PixelFormat::R16U}),
        depth_rays(context, {"ibr depth rays", camera.depth.intrinsics.width,
                             camera.depth.intrinsics.height * s.views, PixelFormat::RGBA32F}),
        points(context, {"ibr points", camera.depth.intrinsics.width, camera.depth.intrinsics.height * s.views,
                         PixelFormat::RGBA32F}),
        color(context, {"ibr color", camera.color.intrinsics.width, camera.color.intrinsics.height * s.views,
                         PixelFormat::RGBA8}),
        fusion(context, passes::fusion_buffer_desc(s.width, s.height)),
        fused_depth(context, {"ibr fused depth", s.width, s.height, PixelFormat::R32F}),
        carved_depth(context, {"ibr carved depth", s.width, s.height, PixelFormat::R32F}),
        refined_depth(context, {"ibr refined depth", s.width, s.height, PixelFormat::R32F}),
        point_tiles(context, "ibr point tiles", camera.depth.intrinsics.width, camera.depth.intrinsics.height, s.views) {
    if (!split) {
      tiles = std::make_unique<passes::IbrTiles>(context, "ibr surface tiles", s.width, s.height);
      return;
    }
    warped = std::make_unique<vk::Image>(context, vk::ImageDesc{"ibr warped", s.width, s.height * s.views, PixelFormat::RGBA32F});
    features =
        std::make_unique<vk::Image>(context, vk::ImageDesc{"ibr features", s.width, s.height * s.views, PixelFormat::RGBA32F});
  }
};

IbrRenderer::IbrRenderer(vk::Context& context, std::vector<passes::IbrCameraModel> cameras, const IbrSettings& settings)
    : context_(context),
      cameras_(std::move(cameras)),
      settings_(with_fusion(settings)),
      foreground_(context, settings_.foreground),
      splat_(context, settings_.splat),
      fuse_(context, settings_.fuse),
      carve_(settings_.carve ? std::make_unique<passes::IbrCarvePass>(context, settings_.carving, settings_.warp.visibility)
                             : nullptr),
      refine_(settings_.refine ? std::make_unique<passes::IbrRefinePass>(context, settings_.refinement,
                                                                                 settings_.warp.visibility) : nullptr),
      scene_(context) {
  if (cameras_.size() < settings_.views)
    throw std::invalid_argument("image-based model: " + std::to_string(settings_.views) + " views asked for, the site has " +
                                std::to_string(cameras_.size()) + " cameras");
  // Checks sizes and poses of every camera once, whichever are selected later.
  for (size_t first = 0; first < cameras_.size(); first += RT_IBR_MAX_VIEWS) {
    const size_t count = std::min<size_t>(RT_IBR_MAX_VIEWS, cameras_.size() - first);
    (void)passes::make_scene_table(cameras_[0].color, std::span(cameras_).subspan(first, count));
  }
  IbrSettings rendered = settings_;
  rendered.width *= settings_.supersample;
  rendered.height *= settings_.supersample;
  const bool split = splits_warp(settings_);
  images_ = std::make_unique<Images>(context, cameras_[0], rendered, split);
  if (settings_.blending == IbrBlending::Lumi)
    lumi_ = std::make_unique<LumiNetBlender>(context, ibr::load_lumi_net(lumi_weights_path(settings_)), rendered.width,
                                             rendered.height, settings_.views);
  else if (split)
    blend_ = std::make_unique<passes::IbrBlendPass>(context, settings_.blend);
  else {
    tiles_ = std::make_unique<passes::IbrTilesPass>(context);
    warp_blend_ = std::make_unique<passes::IbrWarpBlendPass>(context, settings_.views, settings_.warp, settings_.blend);
  }
  if (split) warp_ = std::make_unique<passes::IbrWarpPass>(context, settings_.warp);
  portrait_ = std::make_unique<vk::Image>(context, vk::ImageDesc{"portrait", settings_.width, settings_.height});
  portrait_depth_ = std::make_unique<vk::Image>(
      context, vk::ImageDesc{"portrait depth", settings_.width, settings_.height, PixelFormat::R32F});
  if (settings_.supersample > 1) {
    resolve_ = std::make_unique<passes::IbrResolvePass>(context, settings_.supersample);
    fine_portrait_ = std::make_unique<vk::Image>(context, vk::ImageDesc{"fine portrait", rendered.width, rendered.height});
    fine_portrait_depth_ = std::make_unique<vk::Image>(
        context, vk::ImageDesc{"fine portrait depth", rendered.width, rendered.height, PixelFormat::R32F});
  }

  if (settings_.fill_holes_px > 0) {
    fill_ = std::make_unique<passes::IbrFillPass>(context, settings_.fill_holes_px);
    unfilled_portrait_ =
        std::make_unique<vk::Image>(context, vk::ImageDesc{"unfilled portrait", settings_.width, settings_.height});
    // The warp's surface tiles serve when they are the portrait's; the split path lists the same
    // from the same depth, a supersampled portrait the tiles of its own depth.
    if (!tiles_ || resolve_) {
      fill_tiling_ = std::make_unique<passes::IbrTilesPass>(context, "ibr_fill_tiles");
      fill_tiles_ = std::make_unique<passes::IbrTiles>(context, "ibr fill tiles", settings_.width, settings_.height);
    }
  }

  graph_ = std::make_unique<vk::FrameGraph>(context, "image-based model");
  Images& i = *images_;
  const uint32_t views = settings_.views;
  foreground_.add_to(*graph_, scene_, i.depth_mm, i.depth_rays, i.points, i.point_tiles, views);
  splat_.add_to(*graph_, scene_, i.points, i.point_tiles, i.fusion, views);
  fuse_.add_to(*graph_, i.fusion, i.fused_depth);
  vk::Image* depth = &i.fused_depth;
  if (carve_) {
    carve_->add_to(*graph_, scene_, i.fused_depth, i.points, i.carved_depth, views);
    depth = &i.carved_depth;
  }
  if (refine_) {
    refine_->add_to(*graph_, scene_, *depth, i.color, i.points, i.refined_depth, views);
    depth = &i.refined_depth;
  }
  warp_depth_ = depth;
  vk::Image& resolved = fill_ ? *unfilled_portrait_ : *portrait_;
  vk::Image& blended = resolve_ ? *fine_portrait_ : resolved;
  vk::Image& blended_depth = resolve_ ? *fine_portrait_depth_ : *portrait_depth_;
  if (warp_) warp_->add_to(*graph_, scene_, *depth, i.color, i.points, *i.warped, *i.features, views);
  if (lumi_)
    lumi_->add_to(*graph_, *depth, *i.warped, *i.features, blended, blended_depth, views);
  else if (blend_)
    blend_->add_to(*graph_, *depth, *i.warped, *i.features, blended, blended_depth, views);
  else {
    std::vector<vk::Image*> zeroed{&blended, &blended_depth};
    if (fill_ && !fill_tiles_) zeroed.push_back(portrait_.get());
    tiles_->add_to(*graph_, *depth, *i.tiles, zeroed);
    warp_blend_->add_to(*graph_, scene_, *depth, i.color, i.points, *i.tiles, blended, blended_depth);
  }
  if (resolve_) resolve_->add_to(*graph_, *fine_portrait_, *fine_portrait_depth_, resolved, *portrait_depth_);
  if (fill_tiles_) fill_tiling_->add_to(*graph_, resolve_ ? *portrait_depth_ : *depth, *fill_tiles_, {portrait_.get()});
  if (fill_) fill_->add_to(*graph_, resolved, fill_tiles_ ? *fill_tiles_ : *i.tiles, *portrait_);
}

IbrRenderer::~IbrRenderer() = default;

IbrRenderer::WarpInputs IbrRenderer::warp_inputs() {
  return {table_, *warp_depth_, images_->color, images_->points};
}

void IbrRenderer::prepare(std::span<const sim::RgbdImage> images, std::span<const size_t> selection,
                         const Camera& target_view) {
  if (images.size() != cameras_.size())
    throw std::invalid_argument("image-based model: " + std::to_string(images.size()) + " images for " +
                                std::to_string(cameras_.size()) + " cameras");
  if (selection.size() != settings_.views)
    throw std::invalid_argument("image-based model: " + std::to_string(selection.size()) + " cameras selected, " +
                                std::to_string(settings_.views) + " expected");
  if (target_view.intrinsics.width != settings_.width || target_view.intrinsics.height != settings_.height)
    throw std::invalid_argument("image-based model: the target view is not " + std::to_string(settings_.width) + "x" +
                                std::to_string(settings_.height));
  std::vector<passes::IbrCameraModel> selected;
  std::vector<HostImage> colors, depths;
  for (size_t index : selection) {
    if (index >= cameras_.size()) throw std::invalid_argument("image-based model: camera index out of range");
    const sim::RgbdImage& image = images[index];
    const passes::IbrCameraModel& camera = cameras_[index];
    if (image.color.width != camera.color.intrinsics.width || image.color.height != camera.color.intrinsics.height ||
        image.depth_mm.width != camera.depth.intrinsics.width || image.depth_mm.height != camera.depth.intrinsics.height ||
        image.color.format != PixelFormat::RGBA8 || image.depth_mm.format != PixelFormat::R16U)
      throw std::invalid_argument("image-based model: camera '" + camera.color.name +
                                  "' sent images of another size or format than its calibration");
    selected.push_back(camera);
    colors.push_back(image.color);
    depths.push_back(image.depth_mm);
  }
  Camera rendered_view = target_view;
  if (settings_.supersample > 1) rendered_view.intrinsics = scaled_intrinsics(target_view.intrinsics, settings_.supersample);
  table_ = passes::make_scene_table(rendered_view, selected);
  scene_.write(table_);
  if (uploaded_selection_ != std::vector<size_t>(selection.begin(), selection.end())) {
    vk::upload(context_, images_->depth_rays, passes::depth_ray_atlas(selected));
    uploaded_selection_.assign(selection.begin(), selection.end());
  }
  vk::upload(context_, images_->color, passes::stack_bands(colors));
  vk::upload(context_, images_->depth_mm, passes::stack_bands(depths));
}

std::string blending_description(const IbrRenderer& renderer) {
  const IbrSettings& s = renderer.settings();
  if (!renderer.lumi_net()) return std::string(blending_name(s.blending)) + " (k = " + std::to_string(s.blend.best_views) + ")";
  const ibr::LumiNetShape& shape = renderer.lumi_net()->model().shape;
  return std::string(blending_name(s.blending)) + " (" + lumi_weights_path(s).string() + ", C = " +
         std::to_string(shape.channels) + ", " + std::to_string(shape.blocks) + " blocks, at 1/" +
         std::to_string(shape.scale) + ")";
}

}  // namespace rt::pipeline
