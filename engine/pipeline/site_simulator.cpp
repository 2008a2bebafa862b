#include "pipeline/site_simulator.h"

#include <cmath>
#include <iostream>
#include <stdexcept>

#include "geometry/target_view.h"
#include "sim/face.h"
#include "sim/person_mesh.h"

namespace rt::pipeline {
namespace {

// The face photograph for the users' heads, read once per process; without it the heads are
// plain skin (and the sites fall back to the seat's eye), which is said once.
const std::optional<HostImage>& face_texture() {
  static const std::optional<HostImage> texture = [] {
    std::string why;
    std::optional<HostImage> loaded = sim::load_face_texture(why);
    if (!loaded) std::cerr << "simulator: the users have no face: " << why << "\n";
    return loaded;
  }();
  return texture;
}

std::optional<Camera> ground_truth_view(const sim::Scene& scene, Site site, uint32_t width, uint32_t height) {
  if (width == 0 || height == 0) return std::nullopt;
  // The remote viewer's eye (sim::truth_viewer_eye), mapped into this site's frame.
  const Site remote = other_site(site);
  const Eigen::Vector3d eye = map_point(remote, site, sim::truth_viewer_eye(scene, remote));
  return target_view_camera(eye, scene.at(site).site.screen, width, height);
}

// The user as a marker's flash shows them: the shirt white, so that the whole torso brightens in
// every camera and in the portrait the other site shows.
sim::UserAppearance flashed(sim::UserAppearance user) {
  user.shirt_rgb = user.shirt_stripe_rgb = Eigen::Vector3f::Ones();
  return user;
}

}  // namespace

RgbdCameraSpec camera_spec(const sim::RgbdCamera& camera, const sim::Effects& effects, double resolution_scale) {
  // The rasterizer draws pinhole images; a lens the site describes must not be dropped silently.
  for (const CameraIntrinsics* k : {&camera.color, &camera.depth})
    for (double coefficient : k->distortion.as_opencv())
      if (coefficient != 0.0)
        throw std::invalid_argument("camera '" + camera.name +
                                    "': the simulator renders pinhole cameras; lens distortion is not simulated yet "
                                    "(set its distortion coefficients to 0)");
  RgbdCameraSpec spec;
  spec.name = camera.name;
  spec.color = camera.color_camera();
  spec.depth = camera.depth_camera();
  spec.color.intrinsics = scaled_intrinsics(camera.color, resolution_scale);
  spec.depth.intrinsics = scaled_intrinsics(camera.depth, resolution_scale);
  passes::DepthSensorModel& depth = spec.depth_model;
  depth.range_min_m = float(camera.depth_min_m);
  depth.range_max_m = float(camera.depth_max_m);
  if (effects.near_cutoff) depth.range_min_m = std::max(depth.range_min_m, float(effects.near_cutoff->min_range_m));
  if (effects.depth_noise) depth.noise_sigma_at_1m_m = float(effects.depth_noise->sigma_at_1m_m);
  if (effects.skin_depth_bias) depth.skin_bias_m = float(effects.skin_depth_bias->bias_m);
  if (effects.flying_pixels) {
    depth.flying_edge_m = float(effects.flying_pixels->edge_threshold_m);
    depth.flying_probability = float(effects.flying_pixels->probability);
  }
  if (effects.misregistration) {
    // Given in color pixels; the depth image is shifted by as many of its own pixels.
    const double ratio = spec.depth.intrinsics.fx / spec.color.intrinsics.fx;
    depth.shift_x = int(std::lround(effects.misregistration->pixels_x * ratio));
    depth.shift_y = int(std::lround(effects.misregistration->pixels_y * ratio));
  }
  if (effects.color_gain) {
    const sim::CameraColor color = effects.color_gain->for_camera(camera.name);
    spec.color_model = {float(color.gain), float(color.white_balance.x()), float(color.white_balance.y()),
                         float(color.white_balance.z())};
  }
  return spec;
}

SiteSimulator::SiteSimulator(vk::Context& context, const sim::Scene& scene, Site site, uint32_t target_width,
                             uint32_t target_height)
    : scene_(scene),
      site_(site),
      motion_(scene.at(site).motion, scene.at(site).site.seat, scene.at(site).user),
      renderer_(context,
                [&] {
                  std::vector<RgbdCameraSpec> specs;
                  for (const auto& camera : scene.at(site).site.cameras)
                    specs.push_back(camera_spec(camera, scene.effects, scene.resolution_scale));
                  return specs;
                }(),
                ground_truth_view(scene, site, target_width, target_height), scene.color_supersampling,
                face_texture()),
      timing_random_(scene.seed * 2 + (site == Site::A ? 0 : 1)) {}

std::optional<sim::RgbdFrame> SiteSimulator::next_frame() {
  if (next_ >= scene_.frame_count) return std::nullopt;
  const uint64_t index = next_++;
  const double t_s = double(index) / scene_.fps;
  pose_ = motion_.pose_at(t_s);
  const sim::UserAppearance& user = scene_.at(site_).user;
  const auto mesh = scene_.effects.av_marker && scene_.effects.av_marker->flashing_at(t_s)
                        ? sim::person_mesh(pose_, flashed(user), scene_.mesh_detail)
                        : sim::person_mesh(pose_, user, scene_.mesh_detail);
  renderer_.render(mesh, uint32_t(scene_.seed * 1000003u + index * 2u + (site_ == Site::A ? 0u : 1u)));

  sim::RgbdFrame frame;
  frame.index = index;
  frame.timestamp_us = uint64_t(std::llround(t_s * 1e6));
  for (size_t k = 0; k < renderer_.camera_count(); ++k) {
    sim::RgbdImage image;
    image.camera = renderer_.camera(k).name;
    image.timestamp_us = frame.timestamp_us;
    if (scene_.effects.camera_timing_jitter) {  // only drawn when asked for: off costs nothing
      std::normal_distribution<double> jitter_ms(0.0, scene_.effects.camera_timing_jitter->sigma_ms);
      image.timestamp_us = uint64_t(std::max<int64_t>(0, int64_t(frame.timestamp_us) +
                                                             std::llround(jitter_ms(timing_random_) * 1000.0)));
    }
    image.color = renderer_.color(k);
    image.depth_mm = renderer_.depth_mm(k);
    frame.cameras.push_back(std::move(image));
  }
  return frame;
}

}  // namespace rt::pipeline
