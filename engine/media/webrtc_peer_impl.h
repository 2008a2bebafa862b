#pragma once
// WebRtcPeer's state: the pipeline's elements, the channels, what waits to be paired, the
// counters. In a header of its own so that the peer's implementation can span files; not for
// other modules.
#include <gst/app/gstappsink.h>
#include <gst/gst.h>
#include <gst/video/video.h>
#include <gst/webrtc/webrtc.h>

#include <array>
#include <atomic>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "media/bitrate_follower.h"
#include "media/call_feedback.h"
#include "media/codec_probes.h"
#include "media/frame_time_sei.h"
#include "media/portrait_frame.h"
#include "media/webrtc_peer.h"

namespace rt::media {

// One incoming RTP stream: depayloader, decoder, appsink, and the RTP time of its packets.
struct IncomingChain {
  WebRtcPeer::Impl* impl = nullptr;
  std::array<std::pair<GstClockTime, uint32_t>, 64> pts_to_rtp{};
  size_t next = 0;
  uint32_t last_rtp = 0;
  uint32_t sender_minus_header = 0;  // the sender's RTP time less the header's (media/frame_time_sei.h)
  FrameTimeSei frame_time;
  // Colour or depth and alpha: by payload type (96, 97) until the first picture, then by what it
  // decodes to (an SFU may offer both under one payload type of its own).
  std::atomic<bool> color{false};
  CodecClock decode;
  KeyframeRequests asked;  // by its depayloader, of the other peer's encoder
  TrackLosses losses;
  StalledTrack stalled;
};

struct ByteCount {
  WebRtcPeer::Impl* impl;
  uint64_t* total;
};

struct PendingFrame {
  uint64_t order = 0;          // arrival order while pending
  std::vector<uint8_t> rgb;     // colour, width*height*3
  DepthAlphaCodes codes;         // depth/alpha, width*height each
  // Not an optional: GCC 12 sees a moved-from optional as maybe uninitialized.
  PortraitFrame frame;
  bool has_frame = false;
};

struct WebRtcPeer::Impl {
  WebRtcPeerOptions options;
  Signalling signalling;
  GstElement* pipeline = nullptr;
  GstElement* webrtc = nullptr;
  GstElement* color_src = nullptr;
  GstElement* depth_src = nullptr;
  GstElement* color_enc = nullptr;
  GstElement* depth_enc = nullptr;
  GstElement* netsim = nullptr;  // the simulated network, when the options ask for one
  std::unique_ptr<BitrateFollower> bitrate;
  GstWebRTCDataChannel* fast = nullptr;
  GstWebRTCDataChannel* reliable = nullptr;
  GstWebRTCDataChannel* relayed_in = nullptr;  // relayed: the other site's channel, as the SFU named it
  uint32_t sent_width = 0, sent_height = 0;  // the pictures' size now (media/portrait_size_rule.h)
  CodecClock color_encode, depth_encode;
  FrameTimeSei color_frame_time, depth_frame_time;  // each encoder's pictures stamped with their time
  KeyframeRequests asked_of_us;
  std::vector<std::unique_ptr<IncomingChain>> chains;
  std::deque<ByteCount> byte_counts;  // a deque: the probes hold pointers into it
  RetransmissionWatch retransmission;
  VoiceTrack voice;

  mutable std::mutex mutex;
  bool offered = false;
  GstClockTime last_pts = 0;
  bool sent_any = false;
  uint64_t pending_order = 0;
  std::map<uint32_t, PendingFrame> pending;
  std::deque<PendingFrame> paired;  // `order` is when it was paired, µs
  std::vector<net::Message> messages;
  WebRtcCounters counters;
  std::string last_error;

  // Here rather than in ~WebRtcPeer, so that a constructor that throws half way still stops
  // and frees what it made.
  ~Impl() {
    if (!pipeline) return;
    if (bitrate) bitrate->stop();  // it reads webrtcbin's statistics
    g_signal_handlers_disconnect_by_data(webrtc, this);
    for (GstWebRTCDataChannel* channel : {fast, reliable, relayed_in})
      if (channel) g_signal_handlers_disconnect_by_data(channel, this);
    gst_element_set_state(pipeline, GST_STATE_NULL);
    for (GstWebRTCDataChannel* channel : {fast, reliable, relayed_in})
      if (channel) gst_object_unref(channel);
    bitrate.reset();
    for (GstElement* e : {webrtc, color_src, depth_src, color_enc, depth_enc, netsim})
      if (e) gst_object_unref(e);
    gst_object_unref(pipeline);
  }

  void fail(const std::string& why) {
    std::lock_guard lock(mutex);
    last_error = why;
  }
  void refuse(const std::string& why) {
    std::lock_guard lock(mutex);
    ++counters.messages_refused;
    last_error = why;
  }

  // ---- offer and answer ----
  void maybe_offer();
  // NACK and retransmission on every transceiver, before the offer or answer names them.
  void ask_for_retransmission();
  static void on_offer_created(GstPromise* promise, gpointer data);
  void announce_local(GstWebRTCSessionDescription* description, const char* type);

  // webrtcbin's inner elements as it makes them: RTCP's pace, and the repair's counters.
  void on_element_added(GstElement* element);

  // ---- receiving ----
  void adopt_channel(GstWebRTCDataChannel* channel);
  // The channels this peer opens itself: both, or (relayed) the reliable one only.
  void open_channels();
  void on_channel_bytes(GstWebRTCDataChannel* channel, GBytes* bytes);
  // The bytes as they are, or sealed with the guard, on an open channel; false if it is not open.
  bool send_on_channel(bool on_fast, std::span<const uint8_t> bytes, bool seal = false);
  bool send_handshake_frame(std::span<const uint8_t> frame) {
    return options.handshake_out ? options.handshake_out(frame) : send_on_channel(false, frame);
  }
  bool channels_open() const;
  void link_incoming(GstPad* pad);
  void on_sample(GstAppSink* sink, IncomingChain& chain);
  void store_part(uint32_t rtp, std::vector<uint8_t>* rgb, DepthAlphaCodes* codes, std::optional<PortraitFrame> frame,
                  bool scaled = false);
  static ReceivedPortrait assemble(PendingFrame part);
};

}  // namespace rt::media
