#pragma once
// The sender of one site (DESIGN.md section 1, paper section 3.3): renders this site's user for
// the remote viewer's eye and sends it, with the tracked hands and the local eye.
//
//   capture  (scene clock)  simulated, replayed or live RGBD frame set -> mailbox; the ground
//                           truth of it (simulated)
//   ibr      newest frame + remote eye -> portrait (RGBA + depth) -> network
//   tracker  (50 Hz)        local skeletons (simulated, replayed, or the Leap service's newest
//                           frame) -> network, touch loop; local eye -> network
//
// Each loop runs on its own thread (site_run.cpp starts them); a stage that falls behind drops
// stale frames rather than queueing them.
#include <Eigen/Core>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "camera/k4a_live_site.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/limb_truth.h"
#include "pipeline/recorded_depth_registration.h"
#include "pipeline/site_simulator.h"
#include "session/latency_stats.h"
#include "session/mailbox.h"
#include "site/displayed_truth.h"
#include "site/site_common.h"
#include "site/site_eye.h"
#include "site/site_inputs.h"
#include "touch/site_touch_loop.h"
#include "tracker/leap_service.h"

namespace rt::site {

class Sender {
 public:
  // Opens this site's inputs (a replay updates common.scene) and the image-based model; with
  // --tracker leap, connects to the Leap service first (an error at once when none answers).
  Sender(SiteCommon& common, SiteTouchLoop& touch);

  void capture_loop();
  void ibr_loop();
  void tracker_loop();
  // Ends the loops that wait on frames (a stage failed).
  void stop();

  // The remote viewer's eye, in this site's frame (from the network).
  void set_remote_eye(const Eigen::Vector3d& eye);
  uint64_t last_scene_frame() const { return last_scene_frame_; }
  // Whether the cameras are the simulator's (the scene's truth is then known).
  bool simulated() const { return simulator_ != nullptr; }
  // The image-based model's graph: its images are the window's debug views.
  const vk::FrameGraph& ibr_graph() const;
  void add_metrics(nlohmann::json& metrics, double wall_s) const;

 private:
  struct CapturedFrame {
    uint64_t index = 0;
    uint64_t capture_us = 0;  // monotonic, when the cameras' images were taken
    double scene_time_s = 0;  // of the frame, for the tracked hands of that moment
    sim::RgbdFrame frame;
  };
  std::optional<HostImage> ground_truth(uint64_t index, bool& told_no_truth);
  // Opens the site file's live devices (at least `cameras_needed`); the frame count becomes
  // open-ended unless --frames gave one.
  std::vector<passes::IbrCameraModel> open_live_site(size_t cameras_needed);
  // A real camera's depth registered into its colour image (recorded or live): the GPU's turn.
  void register_depth(sim::RgbdFrame& frame);
  void look_for_eyes_before_the_call();

  SiteCommon& common_;
  SiteTouchLoop& touch_;
  // The site's inputs (site_inputs.h): simulated from the scene, replayed from a recording, or
  // live from the k4a devices its site file names (camera/k4a_live_site.h).
  std::unique_ptr<pipeline::SiteSimulator> simulator_;
  std::unique_ptr<SiteReplay> replay_;
  std::unique_ptr<camera::k4a::LiveSite> live_;
  // A real device's depth into its colour image, recorded or live alike.
  std::unique_ptr<pipeline::RecordedDepthRegistration> registration_;
  std::unique_ptr<devices::LeapServiceTracker> leap_;  // --tracker leap: the hands come from it
  // The simulated truth's hand and forearm region, beside the truth (displayed_truth.h).
  std::unique_ptr<pipeline::LimbTruthRenderer> limb_truth_;
  std::unique_ptr<TruthRegionWriter> truth_regions_;
  TrackedHandsHistory tracked_hands_;
  std::unique_ptr<pipeline::IbrRenderer> ibr_;
  std::vector<Eigen::Vector3d> camera_positions_;
  std::unique_ptr<ViewerEyeFinder> eye_finder_;

  session::Mailbox<CapturedFrame> captured_;
  mutable std::mutex eye_mutex_;
  std::optional<Eigen::Vector3d> remote_eye_;

  uint64_t portraits_rendered_ = 0;  // by the ibr loop, which alone counts them
  std::atomic<uint64_t> frames_captured_{0}, portraits_sent_{0}, frames_without_eye_{0}, tracker_ticks_{0},
      last_scene_frame_{0}, truth_frames_{0}, frames_registered_{0};
  session::LatencyStats capture_to_sent_;
  // Wall time of each stage's GPU turn (upload, graph run, download), next to the frame graph's
  // per-pass timestamps.
  session::LatencyStats simulator_wall_, ibr_wall_;
  EyeErrorStats eye_error_;  // per captured frame of the simulator
};

}  // namespace rt::site
