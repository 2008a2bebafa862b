#pragma once
// What the network does to the call, as each end sees it: the other peer's RTCP receiver reports on
// our outgoing tracks (webrtcbin's get-stats), and on the receiving side the pictures a lost packet
// cost and how long each track took to show a correct picture again. A CPU module on GStreamer only.
#include <gst/gst.h>

#include <cstdint>
#include <mutex>
#include <vector>

#include "media/repair_counters.h"
#include "media/stalled_track.h"

namespace rt::media {

// One outgoing RTP stream: what this peer sent and the NACKs it was sent back (both as webrtcbin
// counts them), and what the other peer's last receiver report said of it, once one came.
struct OutgoingStream {
  uint32_t ssrc = 0;
  unsigned payload_type = 0;  // which track (96 colour, 97 depth and alpha), 0 when get-stats names no codec
  uint64_t packets_sent = 0, nacks_received = 0;
  bool reported = false;      // the fields below come from a receiver report
  double fraction_lost = 0;   // over the report's interval, 0..1, after retransmission repaired what it could
  double round_trip_s = -1;
  int64_t packets_lost = 0;   // since the stream began, after repair
  // The highest sequence number the report says arrived: a new report moves it, while get-stats
  // repeats the last one until the next comes.
  uint32_t highest_sequence = 0;
};

// Blocks until webrtcbin answers get-stats (its own threads gather them).
std::vector<OutgoingStream> read_outgoing_streams(GstElement* webrtc);

// One incoming track's losses. The depayloader's input gives packet sequence numbers (a gap is what
// the jitter buffer gave up on: retransmission could not repair it), the decoder's output the
// pictures that came out whole (the depayloader drops the broken ones until a keyframe). An episode
// runs from the first gap to the next picture: its length is how long the track took to recover.
class TrackLosses {
 public:
  void on_packet(uint16_t sequence);
  void on_picture();
  struct Summary {
    uint64_t packets_lost = 0;      // gaps in sequence numbers at the depayloader
    uint64_t episodes = 0;          // losses that broke the track
    uint64_t recovered = 0;         // episodes ended by a correct picture
    double recovery_ms_median = 0, recovery_ms_max = 0;
  };
  Summary summary() const;

 private:
  static constexpr size_t kSamples = 256;
  mutable std::mutex mutex_;
  bool have_sequence_ = false;
  uint16_t last_sequence_ = 0;
  uint64_t packets_lost_ = 0, episodes_ = 0, recovered_ = 0;
  uint64_t episode_started_us_ = 0;  // 0: none open
  std::vector<float> recovery_ms_;
};

// The elements that retransmit, as webrtcbin makes them: give it every element added inside the
// pipeline; it keeps the jitter buffers and retransmission senders and reads their counts.
class RetransmissionWatch {
 public:
  RetransmissionWatch() = default;
  RetransmissionWatch(const RetransmissionWatch&) = delete;
  RetransmissionWatch& operator=(const RetransmissionWatch&) = delete;
  ~RetransmissionWatch();
  void watch(GstElement* element);  // any element: the others are ignored
  RepairCounters read() const;

 private:
  mutable std::mutex mutex_;
  std::vector<GstElement*> jitterbuffers_, senders_;  // a reference held on each
};

}  // namespace rt::media
