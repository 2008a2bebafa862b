#pragma once
// Keeps a call's two encoders at the rate its network carries: once a second it reads from
// webrtcbin what the other peer said of our streams over RTCP (media/call_feedback.h: its NACKs and
// its receiver reports), gives the colour track's BitrateRule (media/bitrate_rule.h) the loss over
// that second from their running counts (one report's own fraction covers too few packets: one
// loss in a dozen reads as 8 %), then sets x264's bitrate, which it takes while playing. The depth track codes at constant quality under a ceiling; the ceiling moves with
// colour's rate in proportion, so that both give way together. When colour's rate sits at its
// floor, the portrait's size gives way next (media/portrait_size_rule.h): the follower keeps the
// step, the sender reads it. Its own thread; stops before the pipeline does.
#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <thread>

#include "media/bitrate_rule.h"
#include "media/portrait_size_rule.h"

namespace rt::media {

struct BitrateFollowerState {
  int color_kbps = 0, depth_kbps = 0;
  double fraction_lost = 0, round_trip_ms = -1;  // over the last second, the worse track's
  uint64_t decisions = 0, lowered = 0, raised = 0;  // seconds of feedback weighed, and what they did
  int portrait_step = 0;  // media/portrait_size_rule.h: 0 is the call's size
  uint64_t size_steps_down = 0, size_steps_up = 0;
};

class BitrateFollower {
 public:
  // With `adapt` false it only reads the reports (the rates and the size stay where the options
  // put them); with `step_size` false the size does.
  BitrateFollower(GstElement* webrtc, GstElement* color_encoder, GstElement* depth_encoder, BitrateRuleOptions color,
                  int depth_kbps, bool adapt, bool step_size);
  ~BitrateFollower();
  BitrateFollower(const BitrateFollower&) = delete;
  BitrateFollower& operator=(const BitrateFollower&) = delete;
  void stop();
  BitrateFollowerState state() const;

 private:
  void run();
  void follow_reports();

  GstElement* webrtc_;
  GstElement* color_encoder_;
  GstElement* depth_encoder_;
  BitrateRule rule_;
  PortraitSizeRule size_rule_;
  const int color_start_kbps_, depth_start_kbps_;
  const bool adapt_, step_size_;
  // Per outgoing stream (by SSRC: colour, depth, their retransmissions): the reports' running
  // counts when the current second began.
  struct Window {
    bool started = false;
    uint64_t sent = 0, nacks = 0;
    int64_t lost = 0;
    uint32_t highest = 0;
  };
  std::map<uint32_t, Window> windows_;
  std::chrono::steady_clock::time_point window_start_{};

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  BitrateFollowerState state_;
  std::thread thread_;
};

}  // namespace rt::media
