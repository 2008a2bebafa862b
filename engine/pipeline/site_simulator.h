#pragma once
// One site of a scene, simulated by the engine: the user's pose over time, rendered into the
// site's RGBD cameras with the scene's sensor effects, and the ground truth seen from the
// remote viewer's eye (the target view). Also the RgbdSource of the simulated backend.
#include <memory>
#include <random>

#include "pipeline/rgbd_renderer.h"
#include "sim/motion.h"
#include "sim/rgbd_source.h"
#include "sim/scene.h"

namespace rt::pipeline {

// The per-camera sensor models that a scene's effects ask for (all off by default).
RgbdCameraSpec camera_spec(const sim::RgbdCamera& camera, const sim::Effects& effects, double resolution_scale);

class SiteSimulator : public sim::RgbdSource {
 public:
  // target_width/height: the ground-truth target view; 0 = no ground truth.
  SiteSimulator(vk::Context& context, const sim::Scene& scene, Site site, uint32_t target_width = 0,
                uint32_t target_height = 0);

  std::optional<sim::RgbdFrame> next_frame() override;  // renders the next frame
  uint64_t frames_done() const { return next_; }
  // The next next_frame() renders frame `index` (a live site skips the frames it could not keep up with).
  void seek(uint64_t index) { next_ = index; }
  const sim::PersonPose& last_pose() const { return pose_; }
  RgbdRenderer& renderer() { return renderer_; }
  const sim::SiteDescription& site() const { return scene_.at(site_).site; }

 private:
  const sim::Scene& scene_;
  Site site_;
  sim::MotionTrack motion_;
  RgbdRenderer renderer_;
  std::mt19937_64 timing_random_;
  sim::PersonPose pose_;
  uint64_t next_ = 0;
};

}  // namespace rt::pipeline
