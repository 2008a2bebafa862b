#include "media/bitrate_follower.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "media/call_feedback.h"

namespace rt::media {
namespace {
constexpr auto kFollowPeriod = std::chrono::milliseconds(250);
constexpr auto kDecisionPeriod = std::chrono::seconds(1);
constexpr auto kLongestWindow = std::chrono::seconds(5);
constexpr uint64_t kMinPacketsPerDecision = 100;
constexpr int kDepthFloorKbps = 100;  // below this x264's rate control no longer holds the depth quality
}  // namespace

BitrateFollower::BitrateFollower(GstElement* webrtc, GstElement* color_encoder, GstElement* depth_encoder,
                                 BitrateRuleOptions color, int depth_kbps, bool adapt, bool step_size)
    : webrtc_(GST_ELEMENT(gst_object_ref(webrtc))),
      color_encoder_(GST_ELEMENT(gst_object_ref(color_encoder))),
      depth_encoder_(GST_ELEMENT(gst_object_ref(depth_encoder))),
      rule_(color),
      size_rule_(PortraitSizeRuleOptions{.floor_kbps = color.floor_kbps, .round_trip_high_s = color.round_trip_high_s}),
      color_start_kbps_(color.start_kbps),
      depth_start_kbps_(depth_kbps),
      adapt_(adapt),
      step_size_(adapt && step_size) {
  state_.color_kbps = color.start_kbps;
  state_.depth_kbps = depth_kbps;
  thread_ = std::thread([this] { run(); });
}

BitrateFollower::~BitrateFollower() {
  stop();
  for (GstElement* e : {webrtc_, color_encoder_, depth_encoder_}) gst_object_unref(e);
}

void BitrateFollower::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

BitrateFollowerState BitrateFollower::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

void BitrateFollower::run() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, kFollowPeriod, [this] { return stopping_; })) {
    lock.unlock();
    follow_reports();
    lock.lock();
  }
}

void BitrateFollower::follow_reports() {
  const auto now = std::chrono::steady_clock::now();
  if (now - window_start_ < kDecisionPeriod) return;
  const std::vector<OutgoingStream> streams = read_outgoing_streams(webrtc_);
  if (streams.empty()) return;
  // The receiver's loss over the last second: the packets it asked again (NACKs: the loss as the
  // network dealt it, which retransmission then hides from the receiver reports) over the packets
  // sent, pooled over the streams (the tracks share the path, and a small track alone is too few
  // packets: one NACK, often for a packet only late, in a second of 40 read as 2.5 %, past the
  // rule's threshold); or, where more, the loss a stream's reports still count after repair.
  // A second of a small call is a few dozen packets: the window grows until it holds enough of
  // them (or grows old).
  uint64_t sent_in_window = 0;
  for (const OutgoingStream& stream : streams)
    if (const auto w = windows_.find(stream.ssrc); w != windows_.end() && stream.packets_sent > w->second.sent)
      sent_in_window += stream.packets_sent - w->second.sent;
  if (sent_in_window < kMinPacketsPerDecision && now - window_start_ < kLongestWindow && !windows_.empty()) return;
  double lost = -1, round_trip = -1;
  uint64_t sent = 0, nacks = 0;
  for (const OutgoingStream& stream : streams) {
    round_trip = std::max(round_trip, stream.round_trip_s);
    Window& w = windows_[stream.ssrc];
    const Window now_counts{true, stream.packets_sent, stream.nacks_received, stream.packets_lost, stream.highest_sequence};
    if (w.started && stream.packets_sent > w.sent) {
      sent += stream.packets_sent - w.sent;
      nacks += stream.nacks_received - std::min(stream.nacks_received, w.nacks);
      double fraction = 0;
      if (stream.reported && stream.highest_sequence > w.highest)
        fraction = double(stream.packets_lost - w.lost) / double(stream.highest_sequence - w.highest);
      lost = std::max(lost, std::clamp(fraction, 0.0, 1.0));
    }
    w = now_counts;
  }
  if (sent > 0) lost = std::max(lost, std::min(1.0, double(nacks) / double(sent)));
  window_start_ = now;
  if (lost < 0) return;  // nothing sent in the last second, or the first second
  int color_kbps = 0, depth_kbps = 0;
  {
    std::lock_guard lock(mutex_);
    ++state_.decisions;
    state_.fraction_lost = lost;
    state_.round_trip_ms = round_trip >= 0 ? round_trip * 1e3 : -1;
    if (!adapt_) return;
    const int before = rule_.kbps();
    color_kbps = rule_.on_report(lost, round_trip);
    state_.lowered = rule_.lowered();
    state_.raised = rule_.raised();
    if (step_size_) {
      state_.portrait_step = size_rule_.on_decision(std::chrono::duration<double>(now.time_since_epoch()).count(), color_kbps, lost, round_trip);
      state_.size_steps_down = size_rule_.steps_down();
      state_.size_steps_up = size_rule_.steps_up();
    }
    if (color_kbps == before) return;
    depth_kbps = std::max(kDepthFloorKbps, int(std::lround(double(depth_start_kbps_) * color_kbps / color_start_kbps_)));
    state_.color_kbps = color_kbps;
    state_.depth_kbps = depth_kbps;
  }
  g_object_set(color_encoder_, "bitrate", guint(color_kbps), nullptr);
  g_object_set(depth_encoder_, "bitrate", guint(depth_kbps), nullptr);
}

}  // namespace rt::media
