#include "media/call_feedback.h"

#include <gst/webrtc/webrtc.h>

#include <algorithm>
#include <map>
#include <string>

#include "time/monotonic_clock.h"

namespace rt::media {

std::vector<OutgoingStream> read_outgoing_streams(GstElement* webrtc) {
  GstPromise* promise = gst_promise_new();
  g_signal_emit_by_name(webrtc, "get-stats", nullptr, promise);
  std::vector<OutgoingStream> streams;
  if (gst_promise_wait(promise) != GST_PROMISE_RESULT_REPLIED) {
    gst_promise_unref(promise);
    return streams;
  }
  const GstStructure* stats = gst_promise_get_reply(promise);
  // The codecs by their id, for the payload type a stream carries; the receiver reports by the id
  // of the outgoing stream they describe.
  std::map<std::string, unsigned> payload_of_codec;
  std::map<std::string, const GstStructure*> report_of_stream;
  std::vector<const GstStructure*> outbound;
  for (int i = 0, n = stats ? gst_structure_n_fields(stats) : 0; i < n; ++i) {
    const GValue* value = gst_structure_get_value(stats, gst_structure_nth_field_name(stats, i));
    if (!value || !GST_VALUE_HOLDS_STRUCTURE(value)) continue;
    const GstStructure* s = gst_value_get_structure(value);
    GstWebRTCStatsType type{};
    if (!gst_structure_get(s, "type", GST_TYPE_WEBRTC_STATS_TYPE, &type, nullptr)) continue;
    if (type == GST_WEBRTC_STATS_CODEC) {
      unsigned payload = 0;
      if (const char* id = gst_structure_get_string(s, "id"); id && gst_structure_get_uint(s, "payload-type", &payload))
        payload_of_codec[id] = payload;
    } else if (type == GST_WEBRTC_STATS_REMOTE_INBOUND_RTP) {
      if (const char* local = gst_structure_get_string(s, "local-id")) report_of_stream[local] = s;
    } else if (type == GST_WEBRTC_STATS_OUTBOUND_RTP) {
      outbound.push_back(s);
    }
  }
  for (const GstStructure* s : outbound) {
    OutgoingStream stream;
    gst_structure_get_uint(s, "ssrc", &stream.ssrc);
    if (const char* codec = gst_structure_get_string(s, "codec-id"))
      if (const auto found = payload_of_codec.find(codec); found != payload_of_codec.end()) stream.payload_type = found->second;
    guint64 sent = 0;
    guint nacks = 0;
    if (gst_structure_get_uint64(s, "packets-sent", &sent)) stream.packets_sent = sent;
    if (gst_structure_get_uint(s, "nack-count", &nacks)) stream.nacks_received = nacks;
    const char* id = gst_structure_get_string(s, "id");
    const auto report = id ? report_of_stream.find(id) : report_of_stream.end();
    if (report != report_of_stream.end()) {
      const GstStructure* r = report->second;
      const GstStructure* source = nullptr;
      if (const GValue* v = gst_structure_get_value(r, "gst-rtpsource-stats"); v && GST_VALUE_HOLDS_STRUCTURE(v))
        source = gst_value_get_structure(v);
      guint highest = 0;
      if (source && gst_structure_get_uint(source, "rb-exthighestseq", &highest)) {
        stream.reported = true;
        stream.highest_sequence = highest;
        gst_structure_get_double(r, "fraction-lost", &stream.fraction_lost);
        gst_structure_get_double(r, "round-trip-time", &stream.round_trip_s);
        gint64 lost = 0;
        if (gst_structure_get_int64(r, "packets-lost", &lost)) stream.packets_lost = lost;
      }
    }
    streams.push_back(stream);
  }
  gst_promise_unref(promise);
  return streams;
}

void TrackLosses::on_packet(uint16_t sequence) {
  std::lock_guard lock(mutex_);
  if (have_sequence_) {
    const uint16_t gap = uint16_t(sequence - last_sequence_ - 1);
    // A packet behind the last (reordered or repeated) is no loss; a gap ahead is.
    if (gap != 0 && gap < 0x8000) {
      packets_lost_ += gap;
      if (!episode_started_us_) {
        episode_started_us_ = monotonic_now_us();
        ++episodes_;
      }
    }
    if (gap >= 0x8000) return;
  }
  have_sequence_ = true;
  last_sequence_ = sequence;
}

void TrackLosses::on_picture() {
  std::lock_guard lock(mutex_);
  if (!episode_started_us_) return;
  const float ms = float(double(monotonic_now_us() - episode_started_us_) * 1e-3);
  episode_started_us_ = 0;
  ++recovered_;
  if (recovery_ms_.size() == kSamples) recovery_ms_.erase(recovery_ms_.begin());
  recovery_ms_.push_back(ms);
}

TrackLosses::Summary TrackLosses::summary() const {
  std::lock_guard lock(mutex_);
  Summary out;
  out.packets_lost = packets_lost_;
  out.episodes = episodes_;
  out.recovered = recovered_;
  if (!recovery_ms_.empty()) {
    std::vector<float> sorted = recovery_ms_;
    std::sort(sorted.begin(), sorted.end());
    out.recovery_ms_median = sorted[sorted.size() / 2];
    out.recovery_ms_max = sorted.back();
  }
  return out;
}

RetransmissionWatch::~RetransmissionWatch() {
  for (GstElement* element : jitterbuffers_) gst_object_unref(element);
  for (GstElement* element : senders_) gst_object_unref(element);
}

void RetransmissionWatch::watch(GstElement* element) {
  GstElementFactory* factory = gst_element_get_factory(element);
  if (!factory) return;
  const std::string kind = GST_OBJECT_NAME(factory);
  std::lock_guard lock(mutex_);
  if (kind == "rtpjitterbuffer") jitterbuffers_.push_back(GST_ELEMENT(gst_object_ref(element)));
  else if (kind == "rtprtxsend") senders_.push_back(GST_ELEMENT(gst_object_ref(element)));
}

RepairCounters RetransmissionWatch::read() const {
  std::lock_guard lock(mutex_);
  RepairCounters out;
  for (GstElement* jitterbuffer : jitterbuffers_) {
    GstStructure* stats = nullptr;
    g_object_get(jitterbuffer, "stats", &stats, nullptr);
    if (!stats) continue;
    guint64 value = 0;
    if (gst_structure_get_uint64(stats, "num-lost", &value)) out.packets_given_up += value;
    if (gst_structure_get_uint64(stats, "num-late", &value)) out.packets_late += value;
    if (gst_structure_get_uint64(stats, "rtx-count", &value)) out.retransmissions_asked += value;
    if (gst_structure_get_uint64(stats, "rtx-success-count", &value)) out.retransmissions_arrived += value;
    gst_structure_free(stats);
  }
  for (GstElement* sender : senders_) {
    guint requests = 0, packets = 0;
    g_object_get(sender, "num-rtx-requests", &requests, "num-rtx-packets", &packets, nullptr);
    out.retransmissions_requested_of_us += requests;
    out.retransmissions_sent += packets;
  }
  return out;
}

}  // namespace rt::media
