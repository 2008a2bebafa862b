#pragma once
// The voice as an RTP audio track on the call's webrtcbin (media/webrtc_peer.h), beside the
// portrait's two video tracks. The site's own libopus encoder (media/opus_voice.h) makes the
// packets; they go into an appsrc as audio/x-opus, through rtpopuspay (payload type 111), one 20 ms
// packet per RTP packet, their RTP time the capture time (media/voice_rtp_time.h). The receiver
// reads each RTP packet as webrtcbin's jitter buffer hands it out, in order: its sequence number,
// its RTP time and its payload, the Opus packet as it was sent. No depayloader: rtpopusdepay would
// only take the payload out, and its buffers no longer carry the sequence number, which the
// site's own jitter buffer needs to see a lost frame and have the decoder conceal it.
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "media/voice_rtp_time.h"
#include "net/messages.h"

typedef struct _GstElement GstElement;
typedef struct _GstPad GstPad;
typedef struct _GstBuffer GstBuffer;

namespace rt::media {

inline constexpr int kVoicePayloadType = 111;

// The sending branch of webrtcbin's launch line, to its third sink pad (`webrtc.`).
std::string voice_track_description();

// One of webrtcbin's jitter buffers as it is made (one per incoming stream): if its first packet
// turns out to be the voice's, it waits `latency_ms` rather than the call's latency for a missing
// packet, so that the packets after a lost one are not held back longer than the voice's own jitter
// buffer can wait; the voice's decoder conceals what it gives up.
void watch_jitter_buffer_for_voice(GstElement* jitter_buffer, int latency_ms);

struct ReceivedVoice {
  uint32_t sequence = 0;  // the RTP sequence number, extended to 32 bits
  uint32_t rtp_time = 0;  // the capture time, in 48 kHz ticks of the sender's clock (wraps)
  std::vector<uint8_t> packet;  // one Opus packet
};

// The voice frame a received packet is, as the direct session would have handed it out: its capture
// time on the sender's clock (`sender_clock_us`: a recent reading of that clock), its sequence, and
// its length from the Opus packet itself. Empty for a packet Opus does not read as one frame.
std::optional<net::VoiceMessage> voice_message_of(const ReceivedVoice& received, uint64_t sender_clock_us);

struct VoiceTrackCounters {
  uint64_t packets_sent = 0, bytes_sent = 0;          // Opus payload bytes
  uint64_t packets_received = 0, packets_lost = 0;    // lost: gaps past repair, in sequence numbers
  uint64_t packets_refused = 0, packets_dropped = 0;  // refused: empty or over Opus's 1275 bytes;
                                                      // dropped: not taken in time (the oldest go)
  bool retransmission = false;                        // NACK asked for on this track
};

class VoiceTrack {
 public:
  VoiceTrack() = default;
  VoiceTrack(const VoiceTrack&) = delete;
  VoiceTrack& operator=(const VoiceTrack&) = delete;
  ~VoiceTrack();

  // The appsrc of voice_track_description(), named in `pipeline`. Pushes one packet of silence
  // that goes no further than the appsrc, to give webrtcbin's pad the caps an offer or answer needs.
  // `retransmission`: whether NACK is asked for on the track (for its counters).
  void attach_sender(GstElement* pipeline, bool retransmission);
  // One Opus packet of a 20 ms frame captured at `capture_us` (the site's monotonic clock).
  // False before attach_sender.
  bool send(std::span<const uint8_t> packet, uint64_t capture_us, uint32_t frame_samples);
  // An incoming RTP pad of encoding OPUS: an appsink that keeps its packets for take().
  void link_incoming(GstElement* pipeline, GstPad* pad);
  std::vector<ReceivedVoice> take();
  VoiceTrackCounters counters() const;

 private:
  void on_packet(GstBuffer* buffer);

  GstElement* src_ = nullptr;
  mutable std::mutex mutex_;
  SequenceExtender sequences_;
  bool have_sequence_ = false;
  uint32_t last_sequence_ = 0;
  std::deque<ReceivedVoice> received_;
  VoiceTrackCounters counters_;
};

}  // namespace rt::media
