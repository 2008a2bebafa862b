#pragma once
// The receiver of one site (DESIGN.md section 1, paper section 3.3): shows the remote user to
// this site's user, the image-based portrait fused with the geometry hand near the glass.
//
//   network  remote skeletons (50 Hz) -> a time-ordered history; portraits -> mailbox
//   display  newest portrait -> the remote hands interpolated to its capture time from that
//            history (tracking/skeleton_interpolation.h; none when no skeleton lies within the
//            gap limit) -> geometry hand (skinning, raster) in its view -> Eq. 4, Eq. 5,
//            background -> PNG / MP4; then appearance adaption (Eq. 3) from that same portrait
//            and pose, where the cameras see the hand well.
//
// The hand is drawn for exactly the moment the portrait shows, not taken from renders made for
// other skeletons, so the two representations agree however the streams interleave. The display
// loop runs on its own thread (site_run.cpp starts it) and owns every Vulkan object it uses.
#include <atomic>
#include <mutex>

#include "hand/appearance_adaption.h"
#include "net/messages.h"
#include "session/latency_stats.h"
#include "session/mailbox.h"
#include "site/site_common.h"
#include "site/site_display.h"
#include "tracking/skeleton_interpolation.h"

namespace rt::site {

class Receiver {
 public:
  explicit Receiver(SiteCommon& common);

  // From the network thread: a remote skeleton in the sender's frame and clock, and a portrait.
  void on_skeleton(const net::SkeletonMessage& skeleton);
  void on_portrait(const net::PortraitMessage& portrait, uint64_t arrival_us);

  void display_loop();
  // Ends the display's wait for portraits (a stage failed).
  void stop();

  void add_metrics(nlohmann::json& metrics, double wall_s) const;
  // When site.mp4's first frame was shown (0: no video written); set once display_loop has begun.
  uint64_t first_video_frame_us() const { return first_video_frame_us_; }
  // The portraits' median capture-to-screen latency so far (NaN: none shown yet).
  double portrait_latency_ms() const { return portrait_on_screen_.median(); }
  // The same over the last few seconds of portraits: what the far voice is held to now.
  double recent_portrait_latency_ms() const { return portrait_on_screen_.recent_median(kRecentPortraits); }

 private:
  // About ten seconds of a 30 fps stream: long enough that a burst of late portraits (a start-up,
  // a loaded moment) does not pull the voice after it, short enough to follow a link that changes
  // for good over a long call.
  static constexpr size_t kRecentPortraits = 300;
  struct ReceivedPortrait {
    net::PortraitMessage message;
    uint64_t arrival_us = 0;
  };

  SiteCommon& common_;
  session::Mailbox<ReceivedPortrait> portraits_;
  SkeletonHistory remote_skeletons_;  // sender's frame and clock

  std::atomic<uint64_t> hand_renders_done_{0}, link_lost_frames_{0}, frames_displayed_{0}, portraits_wrong_size_{0};
  // Portraits shown without the mesh hand because no remote skeleton lay within the gap limit of
  // their capture time; those shown with it; appearance adaptions run.
  std::atomic<uint64_t> frames_no_hand_skeleton_gap_{0}, frames_with_hand_{0}, appearance_adaptions_{0};
  // The geometry hand's appearance adaption as of the last displayed frame, for metrics.json.
  mutable std::mutex appearance_mutex_;
  hand::AppearanceStatus appearance_status_;
  nlohmann::json appearance_shading_;  // hand::ShadingFit::to_json of the receiver's hand
  nlohmann::json window_metrics_;  // the window's counts at the display's end (same mutex)
  std::atomic<uint64_t> last_portrait_arrival_us_{0};
  std::atomic<uint64_t> first_video_frame_us_{0};
  // How far in time the drawn hand's pose reaches to the skeletons it was built from (see HandsAtTime).
  session::LatencyStats skeleton_to_portrait_gap_;
  session::LatencyStats portrait_network_, portrait_on_screen_, hand_on_screen_;
  session::LatencyStats hand_wall_, receiver_wall_;  // wall time of the GPU turn (upload, run, download)
  // Where a received portrait waits before its turn begins: in the queue while this loop does the
  // previous frame's work, then for the GPU turn held by another thread.
  session::LatencyStats portrait_queue_wait_, display_turn_wait_;
};

}  // namespace rt::site
