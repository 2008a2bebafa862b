#include "pipeline/rgbd_renderer.h"

#include <stdexcept>

#include "pipeline/site_simulator.h"

namespace rt::pipeline {

// The targets one person_raster draw fills.
struct RgbdRenderer::View {
  vk::Image color, depth_m, part, depth_buffer;
  View(vk::Context& context, const std::string& name, const CameraIntrinsics& k)
      : color(context, {name + " color", k.width, k.height, PixelFormat::RGBA8}),
        depth_m(context, {name + " depth m", k.width, k.height, PixelFormat::R32F}),
        part(context, {name + " part", k.width, k.height, PixelFormat::R32F}),
        depth_buffer(context, {name + " depth buffer", k.width, k.height, PixelFormat::D32F}) {}
  passes::RasterTargets targets() { return {&color, &depth_m, &part, &depth_buffer}; }
  passes::ResolveImages resolve_images() { return {&color, &depth_m, &part}; }
};

// A view as the renderer outputs it, and the supersampled view it resolves from (if any).
struct RgbdRenderer::SampledView {
  View view;
  std::unique_ptr<View> fine;
  SampledView(vk::Context& context, const std::string& name, const CameraIntrinsics& k, uint32_t factor)
      : view(context, name, k),
        fine(factor > 1 ? std::make_unique<View>(context, name + " x" + std::to_string(factor), scaled_intrinsics(k, factor))
                        : nullptr) {}
};

struct RgbdRenderer::CameraImages {
  SampledView color;
  View depth_view;
  vk::Image sensed_color, depth_mm;
  CameraImages(vk::Context& context, const RgbdCameraSpec& spec, uint32_t factor)
      : color(context, spec.name + " color view", spec.color.intrinsics, factor),
        depth_view(context, spec.name + " depth view", spec.depth.intrinsics),
        sensed_color(context, {spec.name + " sensed color", spec.color.intrinsics.width,
                                spec.color.intrinsics.height, PixelFormat::RGBA8}),
        depth_mm(context, {spec.name + " depth mm", spec.depth.intrinsics.width, spec.depth.intrinsics.height,
                           PixelFormat::R16U}) {}
};

namespace {

// Near and far planes of the simulated cameras: nothing of a seated user is nearer than a
// centimetre or farther than ten metres.
constexpr double kNearM = 0.01, kFarM = 10.0;

}  // namespace

RgbdRenderer::RgbdRenderer(vk::Context& context, std::vector<RgbdCameraSpec> cameras, std::optional<Camera> target_view,
                           uint32_t color_supersampling, const std::optional<HostImage>& face_texture)
    : context_(context),
      cameras_(std::move(cameras)),
      target_view_(std::move(target_view)),
      raster_(context),
      resolve_(context, color_supersampling) {
  if (face_texture) {
    face_texture_ = std::make_unique<vk::Image>(
        context, vk::ImageDesc{"face texture", face_texture->width, face_texture->height, PixelFormat::RGBA32F});
    vk::upload(context, *face_texture_, *face_texture);
  }
  for (const auto& spec : cameras_) {
    // A color effect that is off costs nothing: without one there is no color_sensor pass.
    const passes::ColorSensorModel& model = spec.color_model;
    const bool identity = model.gain == 1.0f && model.balance_r == 1.0f && model.balance_g == 1.0f && model.balance_b == 1.0f;
    color_sensors_.push_back(identity ? nullptr : std::make_unique<passes::ColorSensorPass>(context, model));
    depth_sensors_.push_back(std::make_unique<passes::DepthSensorPass>(context, spec.depth_model));
    images_.push_back(std::make_unique<CameraImages>(context, spec, color_supersampling));
  }
  if (target_view_)
    target_ = std::make_unique<SampledView>(context, "target view", target_view_->intrinsics, color_supersampling);
}

RgbdRenderer::~RgbdRenderer() = default;

void RgbdRenderer::build_graph(size_t mesh_capacity) {
  graph_.reset();
  mesh_ = std::make_unique<vk::Buffer>(context_, vk::BufferDesc{"simulated mesh", mesh_capacity * sizeof(passes::MeshVertex)});
  mesh_capacity_ = mesh_capacity;
  graph_ = std::make_unique<vk::FrameGraph>(context_, "simulate frame");
  auto count = [this] { return vertex_count_; };
  for (size_t i = 0; i < cameras_.size(); ++i) {
    const RgbdCameraSpec& spec = cameras_[i];
    CameraImages& images = *images_[i];
    const auto depth_view = passes::raster_view(spec.depth, kNearM, kFarM);
    add_sampled_view(spec.color, images.color, "color " + spec.name);
    if (color_sensors_[i])
      color_sensors_[i]->add_to(*graph_, images.color.view.color, images.sensed_color, "color_sensor " + spec.name);
    // Depth does not see the face's colors: the depth views draw plain heads.
    raster_.add_to(*graph_, *mesh_, count, [depth_view] { return depth_view; }, images.depth_view.targets(),
                   "raster depth " + spec.name);
    // Each camera draws its own noise: mix the camera's index into the frame's seed.
    depth_sensors_[i]->add_to(*graph_, images.depth_view.depth_m, images.depth_view.part, images.depth_mm,
                              [this, i] { return seed_ * 2654435761u + uint32_t(i) * 40503u + 1u; },
                              "depth_sensor " + spec.name);
  }
  if (target_) add_sampled_view(*target_view_, *target_, "target view");
}

void RgbdRenderer::add_sampled_view(const Camera& camera, SampledView& sampled, const std::string& name) {
  auto count = [this] { return vertex_count_; };
  Camera drawn = camera;
  if (sampled.fine) drawn.intrinsics = scaled_intrinsics(camera.intrinsics, resolve_.factor());
  const auto view = passes::raster_view(drawn, kNearM, kFarM);
  View& target = sampled.fine ? *sampled.fine : sampled.view;
  raster_.add_to(*graph_, *mesh_, count, [view] { return view; }, target.targets(), "raster " + name,
                 face_texture_.get());
  if (sampled.fine)
    resolve_.add_to(*graph_, sampled.fine->resolve_images(), sampled.view.resolve_images(), "resolve " + name);
}

void RgbdRenderer::render(std::span<const passes::MeshVertex> mesh, uint32_t seed) {
  if (mesh.size() % 3 != 0) throw std::invalid_argument("simulated mesh: vertex count is not a multiple of 3");
  if (mesh.size() > mesh_capacity_ || !graph_) build_graph(std::max<size_t>({mesh.size(), 3, mesh_capacity_ * 2}));
  if (!mesh.empty()) vk::upload(context_, *mesh_, std::as_bytes(mesh));
  vertex_count_ = uint32_t(mesh.size());
  seed_ = seed;
  graph_->run();
}

HostImage RgbdRenderer::color(size_t camera) const {
  CameraImages& images = *images_.at(camera);
  return vk::download(context_, color_sensors_[camera] ? images.sensed_color : images.color.view.color);
}
HostImage RgbdRenderer::depth_mm(size_t camera) const { return vk::download(context_, images_.at(camera)->depth_mm); }
HostImage RgbdRenderer::foreground(size_t camera) const { return vk::download(context_, images_.at(camera)->color.view.part); }
HostImage RgbdRenderer::depth_view_truth(size_t camera) const {
  return vk::download(context_, images_.at(camera)->depth_view.depth_m);
}

bool RgbdRenderer::has_target_view() const { return target_ != nullptr; }

HostImage RgbdRenderer::target_color() const {
  if (!target_) throw std::logic_error("this renderer has no target view");
  return vk::download(context_, target_->view.color);
}
HostImage RgbdRenderer::target_depth_m() const {
  if (!target_) throw std::logic_error("this renderer has no target view");
  return vk::download(context_, target_->view.depth_m);
}
HostImage RgbdRenderer::target_part() const {
  if (!target_) throw std::logic_error("this renderer has no target view");
  return vk::download(context_, target_->view.part);
}

std::vector<passes::IbrCameraModel> RgbdRenderer::camera_models() const {
  std::vector<passes::IbrCameraModel> models;
  for (const auto& spec : cameras_) models.push_back({spec.color, spec.depth});
  return models;
}

}  // namespace rt::pipeline
