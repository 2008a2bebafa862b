#pragma once
// Renders simulated RGBD cameras, and optionally a target view for ground truth, from a mesh of
// the scene, in one frame graph: per camera the color view (person_raster, color_sensor) and
// the depth view (person_raster, depth_sensor), each at its own resolution and intrinsics.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "passes/common/ibr_scene.h"
#include "passes/color_sensor.h"
#include "passes/depth_sensor.h"
#include "passes/person_raster.h"
#include "passes/supersample_resolve.h"
#include "vulkan/frame_graph.h"

namespace rt::pipeline {

struct RgbdCameraSpec {
  std::string name;
  Camera color;  // intrinsics and pose of the color image
  Camera depth;   // of the depth image
  passes::DepthSensorModel depth_model;
  passes::ColorSensorModel color_model;
};

class RgbdRenderer {
 public:
  // color_supersampling (odd): color views and the target view render at that many times the
  // resolution per axis and resolve to it (box-filtered color, centre-sampled depth and part),
  // as a sensor integrates over its pixels; 1 renders point samples. `face_texture` (rgba32f,
  // sim::load_face_texture) is printed on the heads of the meshes; none leaves them plain skin.
  RgbdRenderer(vk::Context& context, std::vector<RgbdCameraSpec> cameras, std::optional<Camera> target_view = {},
               uint32_t color_supersampling = 1, const std::optional<HostImage>& face_texture = {});
  ~RgbdRenderer();

  // Uploads the mesh and renders every view; `seed` drives the sensor noise of this frame.
  void render(std::span<const passes::MeshVertex> mesh, uint32_t seed);

  size_t camera_count() const { return cameras_.size(); }
  const RgbdCameraSpec& camera(size_t index) const { return cameras_[index]; }
  // Every camera's color and depth calibration, as the image-based model takes them.
  std::vector<passes::IbrCameraModel> camera_models() const;
  HostImage color(size_t camera) const;      // rgba8, as sensed
  HostImage depth_mm(size_t camera) const;    // r16ui millimetres, 0 = invalid
  HostImage foreground(size_t camera) const;  // r32f RT_PART_* in the color view (0 = background)
  HostImage depth_view_truth(size_t camera) const;  // r32f metres in the depth view before the sensor

  bool has_target_view() const;
  const std::optional<Camera>& target_view() const { return target_view_; }
  HostImage target_color() const;  // rgba8 premultiplied: the person over a zero background, alpha its coverage
  HostImage target_depth_m() const; // r32f camera z from the eye, 0 where nothing is
  HostImage target_part() const;    // r32f RT_PART_* (the hand mask is part == RT_PART_HAND)

  vk::FrameGraph& graph() { return *graph_; }

 private:
  struct View;
  struct SampledView;
  struct CameraImages;
  void build_graph(size_t mesh_capacity);
  void add_sampled_view(const Camera& camera, SampledView& sampled, const std::string& name);

  vk::Context& context_;
  std::vector<RgbdCameraSpec> cameras_;
  std::optional<Camera> target_view_;
  passes::PersonRasterPass raster_;
  passes::SupersampleResolvePass resolve_;
  std::unique_ptr<vk::Image> face_texture_;  // null: plain heads
  std::vector<std::unique_ptr<passes::ColorSensorPass>> color_sensors_;
  std::vector<std::unique_ptr<passes::DepthSensorPass>> depth_sensors_;
  std::vector<std::unique_ptr<CameraImages>> images_;
  std::unique_ptr<SampledView> target_;
  std::unique_ptr<vk::Buffer> mesh_;
  size_t mesh_capacity_ = 0;
  uint32_t vertex_count_ = 0;
  uint32_t seed_ = 0;
  std::unique_ptr<vk::FrameGraph> graph_;
};

}  // namespace rt::pipeline
