#include "pipeline/hand_renderer.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "geometry/hand_distance.h"
#include "geometry/site_frames.h"
#include "hand/shape_adaption.h"

namespace rt::pipeline {
namespace {

constexpr double kHandNearM = 0.05, kHandFarM = 20.0;

// hand_color_reduce's least region: a share of the image, and at least 16 pixels.
double min_region_pixels(const HandRendererOptions& options, uint32_t width, uint32_t height) {
  return std::max(16.0, options.min_region_fraction * double(width) * double(height));
}

}  // namespace

HandRenderer::HandRenderer(vk::Context& context, const std::filesystem::path& template_dir, uint32_t width, uint32_t height,
                           const HandRendererOptions& options)
    : context_(context),
      options_(options),
      width_(width),
      height_(height),
      right_(hand::load_hand_template(template_dir, false)),
      left_(hand::load_hand_template(template_dir, true)),
      skinning_(context),
      raster_(context),
      stats_(context),
      reduce_(context),
      transfer_(context, options.appearance_max_contrast),
      shading_stats_(context),
      sampler_(context, "hand skin sampler"),
      appearance_(options.appearance_stale_frames, min_region_pixels(options, width, height)),
      shading_(options.appearance_smoothing, min_region_pixels(options, width, height)),
      raster_shading_(hand::raster_shading(hand::unlit_shading())) {
  if (width == 0 || height == 0) throw std::invalid_argument("hand renderer: the image size must be at least 1x1");
  const size_t vertices = std::max(right_.vertices.size(), left_.vertices.size());
  const size_t indices = std::max(right_.indices.size(), left_.indices.size());
  rest_buffer_ = std::make_unique<vk::Buffer>(context, vk::BufferDesc{"hand rest vertices", vertices * sizeof(shader_abi::HandVertex)});
  indices_ = std::make_unique<vk::Buffer>(context, vk::BufferDesc{"hand indices", indices * sizeof(uint32_t)});
  bones_ = std::make_unique<vk::Buffer>(
      context, vk::BufferDesc{"hand bone transforms", sizeof(passes::BoneMatrices), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true});
  skinned_ = std::make_unique<vk::Buffer>(context, vk::BufferDesc{"hand skinned vertices", vertices * sizeof(shader_abi::SkinnedVertex)});
  partials_ = std::make_unique<vk::Buffer>(
      context, vk::BufferDesc{"hand color partial sums", passes::color_stats_group_count(width, height) * sizeof(shader_abi::ColorStatsPartial)});
  shading_partials_ = std::make_unique<vk::Buffer>(
      context, vk::BufferDesc{"hand shading partial sums", passes::shading_stats_group_count(width, height) * sizeof(shader_abi::ShadingPartial)});
  state_ = std::make_unique<vk::Buffer>(context, vk::BufferDesc{"hand appearance state", sizeof(shader_abi::AppearanceState)});
  // Both templates are written with the same skin texture; the right hand's serves both.
  const HostImage& texture = right_.texture;
  template_texture_ = std::make_unique<vk::Image>(context, vk::ImageDesc{"hand skin texture T", texture.width, texture.height, PixelFormat::RGBA32F});
  adapted_texture_ = std::make_unique<vk::Image>(context, vk::ImageDesc{"hand skin texture T'", texture.width, texture.height, PixelFormat::RGBA32F});
  vk::upload(context, *template_texture_, texture);
  auto image = [&](const std::string& name, PixelFormat format) {
    return std::make_unique<vk::Image>(context, vk::ImageDesc{name, width, height, format});
  };
  color_ = image("hand color", PixelFormat::RGBA32F);
  depth_ = image("hand depth", PixelFormat::R32F);
  mask_ = image("hand mask", PixelFormat::R32F);
  const uint32_t factor = passes::check_hand_supersampling(options.supersampling);
  auto display_image = [&](const std::string& name, PixelFormat format) {
    return std::make_unique<vk::Image>(context, vk::ImageDesc{name, width * factor, height * factor, format});
  };
  if (factor > 1) {
    resolve_.emplace(context, factor);
    fine_color_ = display_image("hand color x" + std::to_string(factor), PixelFormat::RGBA32F);
    fine_depth_ = display_image("hand depth x" + std::to_string(factor), PixelFormat::R32F);
    fine_mask_ = display_image("hand mask x" + std::to_string(factor), PixelFormat::R32F);
  }
  display_normal_ = display_image("hand normal", PixelFormat::RGBA32F);
  display_depth_buffer_ = display_image("hand depth buffer", PixelFormat::D32F);
  template_color_ = image("hand template color", PixelFormat::RGBA32F);
  template_depth_ = image("hand template depth", PixelFormat::R32F);
  template_mask_ = image("hand template mask", PixelFormat::R32F);
  template_normal_ = image("hand template normal", PixelFormat::RGBA32F);
  template_depth_buffer_ = image("hand template depth buffer", PixelFormat::D32F);
  reset_appearance();
  use_template(false);
  std::memset(bones_->mapped(), 0, sizeof(passes::BoneMatrices));
}

HandRenderer::~HandRenderer() = default;

const hand::HandTemplate& HandRenderer::active_template() const { return is_left_ ? left_ : right_; }

void HandRenderer::use_template(bool is_left) {
  is_left_ = is_left;
  const hand::HandTemplate& hand = active_template();
  rest_ = hand.rest;
  rest_vertices_ = hand.vertices;
  vk::upload(context_, *rest_buffer_, std::as_bytes(std::span(rest_vertices_)));
  vk::upload(context_, *indices_, std::as_bytes(std::span(hand.indices)));
  shape_adapted_ = false;
  shape_requested_ = true;
}

void HandRenderer::request_shape_adaption() { shape_requested_ = true; }

void HandRenderer::adapt_shape(const HandSkeleton& skeleton) {
  const hand::HandTemplate& hand = active_template();
  const hand::BoneScales scales = hand::bone_scales(skeleton, hand.rest, {hand.palm_width_m, hand.arm_width_m});
  if (!scales.ok()) return;  // try again at the next well-tracked frame
  rest_ = hand::adapted_rest_skeleton(hand.rest, scales);
  rest_vertices_ = hand::adapt_rest_mesh(hand.vertices, hand.rest, rest_, scales);
  vk::upload(context_, *rest_buffer_, std::as_bytes(std::span(rest_vertices_)));
  shape_adapted_ = true;
  shape_requested_ = false;
}

void HandRenderer::set_pose(const HandSkeleton& skeleton, const Camera& target_view) {
  if (target_view.intrinsics.width != width_ || target_view.intrinsics.height != height_)
    throw std::invalid_argument("hand renderer: the target view is " + std::to_string(target_view.intrinsics.width) + "x" +
                                std::to_string(target_view.intrinsics.height) + ", the renderer " + std::to_string(width_) +
                                "x" + std::to_string(height_));
  view_ = passes::raster_view(target_view, kHandNearM, kHandFarM);
  Camera display_view = target_view;
  if (resolve_) display_view.intrinsics = scaled_intrinsics(target_view.intrinsics, resolve_->factor());
  display_view_ = passes::raster_view(display_view, kHandNearM, kHandFarM);
  if (skeleton.is_left != is_left_) {
    use_template(skeleton.is_left);
    has_pose_ = false;
  }
  const bool confident = skeleton.confidence >= options_.min_confidence;
  if (options_.shape_adaption && shape_requested_ && skeleton.confidence >= options_.shape_adaption_confidence)
    adapt_shape(skeleton);
  const hand::BonePose pose = hand::pose_bones(skeleton, rest_);
  tracked_ = confident && pose.ok();
  if (!pose.ok()) {
    pose_error_ = pose.error;
    return;  // hold the last pose
  }
  pose_error_.clear();
  frames_ = pose.frames;
  forearm_ = hand::forearm_tracked(skeleton, active_template().rest);
  matrices_ = hand::skinning_matrices(frames_, rest_);
  std::memcpy(bones_->mapped(), matrices_.data(), sizeof(matrices_));
  has_pose_ = true;
  hand_distance_m_ = hand_distance_to_screen(skeleton);
}

std::array<Eigen::Vector3d, kDigitCount> HandRenderer::fingertips() const {
  std::array<Eigen::Vector3d, kDigitCount> tips;
  for (int d = 0; d < kDigitCount; ++d) tips[size_t(d)] = hand::posed_tip(frames_, rest_, d);
  return tips;
}

uint32_t HandRenderer::drawn_index_count() const {
  if (!has_pose_) return 0;
  const hand::HandTemplate& hand = active_template();
  return forearm_ ? uint32_t(hand.indices.size()) : hand.hand_index_count;
}

void HandRenderer::add_to(vk::FrameGraph& graph) {
  skinning_.add_to(graph, *rest_buffer_, *bones_, *skinned_, [this] { return uint32_t(rest_vertices_.size()); });
  const passes::HandLayerImages display{color_.get(), mask_.get(), depth_.get()};
  const passes::HandLayerImages drawn = resolve_ ? passes::HandLayerImages{fine_color_.get(), fine_mask_.get(), fine_depth_.get()} : display;
  raster_.add_to(graph, *skinned_, *indices_, [this] { return drawn_index_count(); }, *adapted_texture_, sampler_,
                 [this] { return passes::hand_raster_params(display_view_, raster_shading_); },
                 {drawn.color, drawn.depth_m, drawn.mask, display_normal_.get(), display_depth_buffer_.get()});
  if (resolve_) resolve_->add_to(graph, drawn, display);
}

void HandRenderer::reset_appearance() {
  const shader_abi::AppearanceState empty{};
  vk::upload(context_, *state_, std::as_bytes(std::span(&empty, 1)));
  vk::upload(context_, *adapted_texture_, right_.texture);
  appearance_before_ = empty;
  appearance_.reset();
  shading_.reset();
  raster_shading_ = hand::raster_shading(hand::unlit_shading());
}

shader_abi::AppearanceState HandRenderer::appearance_state() {
  const auto bytes = vk::download(context_, *state_);
  shader_abi::AppearanceState state;
  std::memcpy(&state, bytes.data(), sizeof(state));
  return state;
}

void HandRenderer::build_appearance_graph(vk::Image& portrait_color, vk::Image& portrait_depth) {
  appearance_graph_ = std::make_unique<vk::FrameGraph>(context_, "hand appearance adaption");
  vk::FrameGraph& graph = *appearance_graph_;
  // Skinned here too, so that the fit sees the current pose even where the frame's own render has
  // not run yet (a first fit before the first draw).
  skinning_.add_to(graph, *rest_buffer_, *bones_, *skinned_, [this] { return uint32_t(rest_vertices_.size()); },
                   "hand_skinning_template");
  // The untouched template, unlit: the statistics and the light estimate compare the portrait
  // with the albedo.
  raster_.add_to(graph, *skinned_, *indices_, [this] { return drawn_index_count(); }, *template_texture_, sampler_,
                 [this] { return passes::hand_raster_params(view_, hand::raster_shading(hand::unlit_shading())); },
                 {template_color_.get(), template_depth_.get(), template_mask_.get(), template_normal_.get(),
                  template_depth_buffer_.get()},
                 "hand_raster_template");
  stats_.add_to(graph, portrait_color, portrait_depth, *template_color_, *template_depth_, *template_mask_, *partials_);
  if (options_.appearance_shading)
    shading_stats_.add_to(graph, portrait_color, portrait_depth, *template_color_, *template_depth_, *template_mask_,
                          *template_normal_, *shading_partials_);
  const uint32_t groups = passes::color_stats_group_count(width_, height_);
  const float min_pixels = float(min_region_pixels(options_, width_, height_));
  reduce_.add_to(graph, *partials_, *state_, [groups, min_pixels, smoothing = options_.appearance_smoothing] {
    return shader_abi::ColorStatsReduceParams{groups, min_pixels, smoothing, passes::kSigmaFloor};
  });
  transfer_.add_to(graph, *template_texture_, *state_, *adapted_texture_);
  appearance_portrait_[0] = &portrait_color;
  appearance_portrait_[1] = &portrait_depth;
}

bool HandRenderer::appearance_adaption_possible() const {
  return has_pose_ && tracked_ && appearance_.accepts(hand_distance_m_ > RT_FUSION_D_MAX_M);
}

bool HandRenderer::adapt_appearance_from(vk::Image& portrait_color, vk::Image& portrait_depth) {
  if (!appearance_adaption_possible()) return false;
  if (portrait_color.width() != width_ || portrait_color.height() != height_)
    throw std::invalid_argument("hand renderer: portrait '" + portrait_color.name() + "' differs in size from the hand render");
  if (!appearance_graph_ || appearance_portrait_[0] != &portrait_color || appearance_portrait_[1] != &portrait_depth)
    build_appearance_graph(portrait_color, portrait_depth);
  const bool beyond_d_max = hand_distance_m_ > RT_FUSION_D_MAX_M;
  if (appearance_.restarts_before(beyond_d_max)) reset_appearance();
  appearance_graph_->run();
  const shader_abi::AppearanceState after = appearance_state();
  appearance_.record(appearance_before_, after, beyond_d_max);
  appearance_before_ = after;
  // Not from provisional frames: close to the glass the depth test keeps mostly the forearm, whose
  // normals turn about one axis, and a light fitted there is extrapolated over the palm.
  if (options_.appearance_shading && beyond_d_max) {
    const auto bytes = vk::download(context_, *shading_partials_);
    const std::span partials(reinterpret_cast<const shader_abi::ShadingPartial*>(bytes.data()),
                             passes::shading_stats_group_count(width_, height_));
    shading_.add_frame(hand::add_shading_partials(partials));
    raster_shading_ = hand::raster_shading(shading_.coefficients());
  }
  return true;
}

}  // namespace rt::pipeline
