#include "pipeline/limb_truth.h"

#include <cmath>
#include <stdexcept>

#include "geometry/hand_distance.h"
#include "ibr/camera_selection.h"
#include "sim/person_mesh.h"

namespace rt::pipeline {
namespace {

// Room for a hand and a forearm at the simulator's default detail.
constexpr size_t kMaxLimbVertices = 200000;

}  // namespace

LimbTruthRenderer::LimbTruthRenderer(vk::Context& context, const Camera& view)
    : context_(context),
      width_(view.intrinsics.width),
      height_(view.intrinsics.height),
      view_(passes::raster_view(view, 0.05, 20.0)),
      raster_(context),
      mesh_(context, {"measured limb mesh", kMaxLimbVertices * sizeof(passes::MeshVertex)}),
      color_(context, {"limb color", width_, height_, PixelFormat::RGBA8}),
      depth_(context, {"limb depth", width_, height_, PixelFormat::R32F}),
      part_(context, {"limb part", width_, height_, PixelFormat::R32F}),
      depth_buffer_(context, {"limb depth buffer", width_, height_, PixelFormat::D32F}),
      graph_(context, "limb truth") {
  raster_.add_to(graph_, mesh_, [this] { return vertices_; }, [this] { return view_; },
                 {&color_, &depth_, &part_, &depth_buffer_}, "limb_raster");
}

LimbTruth LimbTruthRenderer::measure(const sim::PersonPose& pose, const sim::UserAppearance& user,
                                     const HostImage& scene_color, const HostImage& scene_depth, const HostImage& scene_part) {
  const bool right = ibr::touching_hand(pose.right_hand, pose.left_hand) == ibr::TouchingHand::Right;
  LimbTruth truth;
  truth.hand = right ? pose.right_hand : pose.left_hand;
  std::vector<passes::MeshVertex> mesh;
  sim::append_hand(mesh, truth.hand, user.hand_scale, user.skin_rgb);
  sim::append_forearm(mesh, right ? pose.right_arm : pose.left_arm, user.skin_rgb);
  if (mesh.size() > kMaxLimbVertices) throw std::logic_error("limb truth: the hand and forearm mesh outgrew its buffer");
  vertices_ = uint32_t(mesh.size());
  vk::upload(context_, mesh_, std::as_bytes(std::span(mesh)));
  graph_.run();
  truth.region = evaluation::hand_region(scene_color, scene_depth, scene_part, vk::download(context_, depth_),
                                         vk::download(context_, part_));
  truth.distance_m = hand_distance_to_screen(truth.hand);
  truth.phase = evaluation::touch_phase(truth.distance_m);
  return truth;
}

}  // namespace rt::pipeline
