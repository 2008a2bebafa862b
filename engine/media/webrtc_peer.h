#pragma once
// One end of a WebRTC call on GStreamer's webrtcbin: the portrait as two video tracks and the
// session's small messages on two data channels (docs/webrtc.md). A CPU module: it owns no
// Vulkan objects; portraits go in and come out as host images.
//
//   colour       appsrc I420 -> x264enc (zerolatency, no B-frames) -> rtph264pay pt 96 -> webrtcbin
//   depth+alpha  appsrc Y444_10LE (media/depth_alpha_codec.h) -> x264enc High 4:4:4 -> pt 97
//   voice        appsrc audio/x-opus (the site's own encoder's packets) -> rtpopuspay pt 111
//                (media/webrtc_voice_track.h)
//   "rt-fast"    unordered, no retransmits: eye, skeletons, and each portrait's frame record
//   "rt-reliable" ordered and reliable: touch events, heartbeats
//
// Both tracks' payloaders start their RTP time at 0 and are fed the same presentation time, so a
// portrait's colour and depth frames carry one RTP timestamp; its frame record names it. Each
// picture carries that time in its bitstream too (media/frame_time_sei.h), which the receiver
// prefers: an SFU may rewrite RTP times. The receiver pairs the three by it and hands out a
// portrait only when all three arrived.
//
// Signalling is the caller's: the offer, the answer and the ICE candidates come out of the
// Signalling callbacks (from GStreamer's threads) and go into the other peer's
// set_remote_description / add_ice_candidate. ICE gathers on the addresses in `local_addresses`
// only (127.0.0.1 by default: libnice skips loopback unless it is named), and from the STUN and
// TURN servers the options name.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "media/channel_guard.h"
#include "media/depth_alpha_codec.h"
#include "media/repair_counters.h"
#include "media/webrtc_voice_track.h"
#include "net/message_codec.h"
#include "net/messages.h"

namespace rt::media {

struct Signalling {
  // type is "offer" or "answer".
  std::function<void(const std::string& type, const std::string& sdp)> on_description;
  std::function<void(unsigned mline, const std::string& candidate)> on_candidate;
};

struct WebRtcPeerOptions {
  std::string name = "peer";
  bool offerer = false;            // exactly one of the two peers makes the offer
  uint32_t width = 1280, height = 720;  // even: the tracks are 4:2:0
  int fps = 30;
  int color_kbps = 2500;  // the colour encoder's target bitrate
  int depth_kbps = 1200;  // the depth encoder's ceiling: it codes at constant quality below it
  int depth_quality = 14; // x264's CRF for depth (lower: finer, more bits)
  int keyframe_interval = 60;                // frames; a lost picture also asks for one
  // The colour bitrate follows the other peer's receiver reports (media/bitrate_rule.h), from
  // color_kbps between this floor and ceiling; the depth track's ceiling moves in proportion.
  bool adapt_bitrate = true;
  int color_floor_kbps = 300, color_ceiling_kbps = 2500;
  // With the colour rate held at its floor, both tracks' pictures step down to 3/4 and 1/2 of the
  // call's size, and back up once the path clears (media/portrait_size_rule.h; only while the
  // bitrate adapts). The receiver scales them back to the call's size.
  bool step_portrait_size = true;
  // Lost packets asked again (RTCP NACK, retransmitted on their own stream) while the jitter buffer
  // can still use them; a picture that retransmission could not repair asks for a keyframe.
  bool retransmit = true;
  // The voice track's own: NACK for the voice, and how long its jitter buffer waits for a missing
  // packet before giving it up (the site's jitter buffer then conceals it); docs/sound.md says why.
  bool voice_retransmit = true;
  int voice_jitter_buffer_ms = 20;
  // Tests and benches only: GStreamer's netsim on the outgoing RTP, after retransmission and before
  // the network, dropping this fraction of packets at random (set_simulated_loss changes it).
  // Negative: no simulator in the path at all.
  double simulated_loss = -1;
  DepthRange depth_range;
  std::vector<std::string> local_addresses = {"127.0.0.1"};
  // ICE servers as media/ice_servers.h checks them (empty: none): a STUN server, a TURN relay, and
  // whether ICE may use the relay only (the test of a call that nothing but the relay carries).
  std::string stun_server, turn_server;
  bool relay_only = false;
  size_t max_queued_portraits = 8;  // received, not yet taken: the oldest is dropped beyond
  // Through an SFU (Janus's VideoRoom), which relays one way per peer connection and carries a
  // publisher's data channels to a subscriber as one ordered, reliable channel named after the
  // publisher. So a relayed peer sends every message on its reliable channel (the offerer: the
  // publisher), takes a channel of any other name as the other site's (the answerer: the
  // subscriber, which opens a channel of its own so that the SFU's side of the association starts),
  // and counts as connected once ICE and its own channel are. The voice goes as a message on the
  // channel too, sealed like the rest: the SFU rewrites an audio track's RTP times, which carry the
  // capture time, and could hear it.
  bool relayed = false;
  // Relayed: where this peer's handshake frames go (the guard's hello and replies). A subscriber
  // cannot answer on its own connection, which the SFU relays nowhere; its site's publisher can
  // (send_handshake). Empty: on this peer's own reliable channel.
  std::function<bool(std::span<const uint8_t>)> handshake_out;
  // The site key on the data channels (media/channel_guard.h): with one, everything they carry
  // is sealed, nothing is sent before its handshake completes, and connected() waits for it.
  // Without one, DTLS alone protects them (the tests of the channels' own checks).
  std::shared_ptr<ChannelGuard> guard;
};

struct ReceivedPortrait {
  net::PortraitMessage portrait;
  uint32_t rtp_timestamp = 0;
  uint64_t received_us = 0;  // this process's monotonic clock, when the last of its parts arrived
                             // (take_portrait then converts it to float images)
};

struct WebRtcCounters {
  uint64_t portraits_sent = 0, portraits_received = 0, portraits_dropped = 0;
  uint64_t frames_unpaired = 0;  // a track's frame, or a frame record, that found no partner in time
  uint64_t messages_sent = 0, messages_received = 0, messages_refused = 0;
  uint64_t messages_early = 0;  // before this side's handshake completed: dropped
  uint64_t color_bytes_sent = 0, depth_bytes_sent = 0, channel_bytes_sent = 0;  // encoded payload bytes
  // The codecs (media/codec_probes.h): median ms a picture spends in each encoder and decoder
  // (0 before any), and the keyframes asked: by this peer's depayloaders of the other peer after a
  // lost picture, and of this peer's encoders (RTCP PLI or FIR from the other side).
  double color_encode_ms = 0, depth_encode_ms = 0, color_decode_ms = 0, depth_decode_ms = 0;
  uint64_t keyframes_asked = 0, keyframes_asked_of_us = 0;
  // The network (media/bitrate_follower.h). Sending: the encoders' bitrates now, the loss the other
  // peer's RTCP showed over the last second (NACKs or reports, the worse track), the round trip,
  // the seconds of feedback the bitrate rule weighed and how often it moved the rate.
  int color_kbps_now = 0, depth_kbps_now = 0;
  double reported_fraction_lost = 0, round_trip_ms = -1;
  uint64_t bitrate_decisions = 0, bitrate_lowered = 0, bitrate_raised = 0;
  // The size both tracks' pictures are encoded at now, and how often the size rule changed it.
  uint32_t width_sent = 0, height_sent = 0;
  uint64_t size_steps_down = 0, size_steps_up = 0;
  // Receiving: pictures that came smaller than the call's size and were scaled back to it.
  uint64_t color_pictures_scaled = 0, depth_pictures_scaled = 0;
  // Receiving: portraits whose record came but not both pictures (lost to the network), and per
  // track the pictures missing from those, the packets lost past repair, the losses that broke the
  // track, those it recovered from with a correct picture and how long that took, and the
  // keyframes its depayloader asked for.
  uint64_t portraits_lost = 0;
  struct TrackLoss {
    uint64_t frames_lost = 0, packets_lost = 0, episodes = 0, recovered = 0, keyframes_asked = 0;
    double recovery_ms_median = 0, recovery_ms_max = 0;
  } color_loss, depth_loss;
  RepairCounters repair;
  VoiceTrackCounters voice;
};

class WebRtcPeer {
 public:
  // Throws std::runtime_error naming the missing GStreamer element (and its Debian package) or a
  // bad option.
  WebRtcPeer(WebRtcPeerOptions options, Signalling signalling);
  ~WebRtcPeer();
  WebRtcPeer(const WebRtcPeer&) = delete;
  WebRtcPeer& operator=(const WebRtcPeer&) = delete;

  // The remote peer's description. Returns an error (a malformed SDP, an offer given to the
  // offerer, a description webrtcbin refuses) or empty.
  std::string set_remote_description(const std::string& type, const std::string& sdp);
  void add_ice_candidate(unsigned mline, const std::string& candidate);

  // Until ICE is connected and both data channels are open; false on timeout or failure.
  bool wait_connected(std::chrono::milliseconds timeout);
  bool connected() const;
  // ICE connected and the data channels open, the guard's handshake done or not.
  bool channels_up() const;

  // Throws std::invalid_argument for a portrait of another size or format. Frames sent before
  // the call is connected are dropped by webrtcbin (the offer needs the tracks' caps, so the first
  // one must be sent before it can be made).
  void send_portrait(const net::PortraitMessage& portrait);
  // Eye and skeletons on the unordered channel, touch events and heartbeats on the reliable one,
  // each as the session's encoded message (net/message_codec.h). A portrait or a voice frame is
  // refused (std::invalid_argument): they travel as video and audio (a relayed peer's voice frames
  // go here: see `relayed`). False when the channel is not open.
  bool send_message(const net::Message& message);
  // Raw bytes on one channel, for what the session's codec would not make: the tests of the
  // receiver's checks (sealed first when there is a guard). False when the channel is not open,
  // before the guard's handshake completed, or for more than 64 KiB (webrtcbin's SCTP would drop
  // it unannounced).
  enum class Channel { Fast, Reliable };
  bool send_raw(Channel channel, std::span<const uint8_t> bytes);
  // A handshake frame of the guard's, unsealed, on the reliable channel (a relayed subscriber's,
  // through its site's publisher). False when the channel is not open.
  bool send_handshake(std::span<const uint8_t> frame);
  // Both encoders' next frame is a keyframe.
  void request_keyframe();
  // The simulated network's loss from now on (0..1); false when the peer was made without one
  // (options.simulated_loss negative) or the call has not created it yet.
  bool set_simulated_loss(double fraction);

  // One Opus packet of a voice frame captured at `capture_us` (this site's monotonic clock): false
  // for an empty or oversized packet or before the track exists. Packets before the call is up are
  // dropped by webrtcbin.
  bool send_voice(std::span<const uint8_t> packet, uint64_t capture_us, uint32_t frame_samples);
  // The voice packets received since the last call, in order, lost ones missing.
  std::vector<ReceivedVoice> take_voice();

  std::optional<ReceivedPortrait> take_portrait();
  std::vector<net::Message> take_messages();
  WebRtcCounters counters() const;
  // The last error seen (refused message, bus error, ...), empty if none.
  std::string last_error() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace rt::media
