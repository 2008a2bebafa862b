#pragma once
// The receiver of one site (DESIGN.md section 1, paper section 3.3): shows the remote user to
// this site's user, the image-based portrait fused with the geometry hand near the glass.
//
//   network  remote skeletons -> history and the hand thread; portraits -> mailbox
//   hand     newest remote skeleton -> geometry hand (skinning, raster) at the portraits' view
//            -> short history of renders; each shown portrait -> appearance adaption (Eq. 3)
//   display  newest portrait + the hand render whose skeleton is closest in time to it ->
//            Eq. 4, Eq. 5, background -> PNG / MP4
//
// The hand and display loops run on their own threads (site_run.cpp starts them).
#include <atomic>
#include <mutex>
#include <optional>

#include "geometry/camera.h"
#include "net/messages.h"
#include "session/latency_stats.h"
#include "session/mailbox.h"
#include "session/timed_history.h"
#include "site/site_common.h"
#include "site/site_display.h"

namespace rt::site {

class Receiver {
 public:
  explicit Receiver(SiteCommon& common);

  // From the network thread: a remote skeleton in the sender's frame and clock, and a portrait.
  void on_skeleton(const net::SkeletonMessage& skeleton);
  void on_portrait(const net::PortraitMessage& portrait, uint64_t arrival_us);

  void hand_loop();
  void display_loop();
  // Ends the display's wait for portraits (a stage failed).
  void stop();

  void add_metrics(nlohmann::json& metrics, double wall_s) const;

 private:
  struct ReceivedPortrait {
    net::PortraitMessage message;
    uint64_t arrival_us = 0;
  };

  SiteCommon& common_;
  session::Mailbox<ReceivedPortrait> portraits_;
  session::TimedHistory<net::SkeletonMessage> remote_skeletons_;  // sender's frame and clock
  // The hand thread: the newest remote skeleton to draw, the view to draw it from (the portraits'
  // camera, sent with each one), the portraits shown (for appearance adaption), its renders.
  session::Mailbox<net::SkeletonMessage> skeletons_to_draw_;
  session::Mailbox<ReceivedPortrait> portraits_shown_;
  std::mutex hand_camera_mutex_;
  std::optional<Camera> hand_camera_;
  session::TimedHistory<HandRender> hand_renders_;
  std::atomic<bool> display_done_{false};

  std::atomic<uint64_t> hand_renders_done_{0}, link_lost_frames_{0}, frames_displayed_{0}, portraits_wrong_size_{0};
  std::atomic<uint64_t> last_portrait_arrival_us_{0};
  session::LatencyStats hand_to_portrait_gap_;  // capture times of the hand render and the portrait fused
  session::LatencyStats portrait_network_, portrait_on_screen_, hand_on_screen_;
  session::LatencyStats hand_wall_, receiver_wall_;  // wall time of the GPU turn (upload, run, download)
};

}  // namespace rt::site
