#include "media/webrtc_voice_track.h"

#include <gst/gst.h>
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/rtp/gstrtpbuffer.h>
#include <opus.h>

namespace rt::media {
namespace {

// Five seconds of 20 ms packets: a taker that stalled longer has lost them anyway.
constexpr size_t kMaxReceivedPackets = 250;
constexpr size_t kMaxOpusPacket = 1275;
// The shortest Opus packet of a 20 ms frame: its table-of-contents byte (CELT, full band, 20 ms,
// mono, one frame) and two bytes that decode to silence.
constexpr uint8_t kSilentOpusPacket[] = {0xF8, 0xFF, 0xFE};

}  // namespace

std::string voice_track_description() {
  // timestamp-offset=0: the RTP time is the presentation time in 48 kHz ticks, and the presentation
  // time is the capture time (webrtc_peer.cpp runs the pipeline on the site's monotonic clock).
  // perfect-rtptime=false: from the timestamps, not from counted samples.
  const std::string pt = std::to_string(kVoicePayloadType);
  return "appsrc name=voicesrc is-live=true format=time do-timestamp=false "
         "caps=audio/x-opus,channel-mapping-family=0,channels=1,rate=48000 ! rtpopuspay name=voicepay pt=" +
         pt + " timestamp-offset=0 perfect-rtptime=false ! application/x-rtp,media=audio,encoding-name=OPUS,clock-rate=48000,payload=" +
         pt + " ! webrtc.";
}

void watch_jitter_buffer_for_voice(GstElement* jitter_buffer, int latency_ms) {
  GstPad* pad = gst_element_get_static_pad(jitter_buffer, "sink");
  if (!pad) return;
  gst_pad_add_probe(pad, GstPadProbeType(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST),
                    +[](GstPad* sink, GstPadProbeInfo* info, gpointer latency) {
                      GstBuffer* buffer = (info->type & GST_PAD_PROBE_TYPE_BUFFER_LIST)
                                              ? gst_buffer_list_get(GST_PAD_PROBE_INFO_BUFFER_LIST(info), 0)
                                              : GST_PAD_PROBE_INFO_BUFFER(info);
                      GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
                      if (!buffer || !gst_rtp_buffer_map(buffer, GST_MAP_READ, &rtp)) return GST_PAD_PROBE_OK;
                      const bool voice = gst_rtp_buffer_get_payload_type(&rtp) == kVoicePayloadType;
                      gst_rtp_buffer_unmap(&rtp);
                      if (voice) {
                        GstElement* element = gst_pad_get_parent_element(sink);
                        if (element) g_object_set(element, "latency", guint(GPOINTER_TO_INT(latency)), nullptr);
                        if (element) gst_object_unref(element);
                      }
                      return GST_PAD_PROBE_REMOVE;
                    },
                    GINT_TO_POINTER(latency_ms), nullptr);
  gst_object_unref(pad);
}

std::optional<net::VoiceMessage> voice_message_of(const ReceivedVoice& received, uint64_t sender_clock_us) {
  const int samples = opus_packet_get_nb_samples(received.packet.data(), opus_int32(received.packet.size()), int(kVoiceRtpClockRate));
  // The frame lengths a voice record may carry (net/messages.h).
  if (samples != 480 && samples != 960 && samples != 1920) return std::nullopt;
  net::VoiceMessage message;
  message.timestamp_us = voice_capture_us(received.rtp_time, sender_clock_us);
  message.sequence = received.sequence;
  message.frame_samples = uint16_t(samples);
  message.packet = received.packet;
  return message;
}

VoiceTrack::~VoiceTrack() {
  if (src_) gst_object_unref(src_);
}

void VoiceTrack::attach_sender(GstElement* pipeline, bool retransmission) {
  src_ = gst_bin_get_by_name(GST_BIN(pipeline), "voicesrc");
  if (!src_) return;
  // webrtcbin holds what reaches its pad before the call is up and sends it once it is: the packet
  // is dropped as it leaves the appsrc, after the caps it carries have gone ahead of it.
  GstPad* pad = gst_element_get_static_pad(src_, "src");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, +[](GstPad* from, GstPadProbeInfo* info, gpointer) {
                      gst_pad_remove_probe(from, GST_PAD_PROBE_INFO_ID(info));
                      return GST_PAD_PROBE_DROP;
                    },
                    nullptr, nullptr);
  gst_object_unref(pad);
  GstClock* clock = gst_element_get_clock(pipeline);
  const uint64_t now_us = clock ? gst_clock_get_time(clock) / 1000 : 0;
  if (clock) gst_object_unref(clock);
  send(kSilentOpusPacket, now_us, 960);
  std::lock_guard lock(mutex_);
  counters_ = {};  // the caps' packet is no part of the call
  counters_.retransmission = retransmission;
}

bool VoiceTrack::send(std::span<const uint8_t> packet, uint64_t capture_us, uint32_t frame_samples) {
  if (!src_ || packet.empty() || packet.size() > kMaxOpusPacket) return false;
  GstBuffer* buffer = gst_buffer_new_memdup(packet.data(), packet.size());
  GST_BUFFER_PTS(buffer) = GstClockTime(capture_us) * GST_USECOND;
  GST_BUFFER_DURATION(buffer) = gst_util_uint64_scale_int(frame_samples, GST_SECOND, int(kVoiceRtpClockRate));
  GST_BUFFER_OFFSET(buffer) = GST_BUFFER_OFFSET_NONE;
  if (gst_app_src_push_buffer(GST_APP_SRC(src_), buffer) != GST_FLOW_OK) return false;
  std::lock_guard lock(mutex_);
  ++counters_.packets_sent;
  counters_.bytes_sent += packet.size();
  return true;
}

void VoiceTrack::link_incoming(GstElement* pipeline, GstPad* pad) {
  GstElement* sink = gst_element_factory_make("appsink", nullptr);
  g_object_set(sink, "sync", FALSE, "max-buffers", 64u, "drop", FALSE, nullptr);
  GstAppSinkCallbacks callbacks{};
  callbacks.new_sample = +[](GstAppSink* s, gpointer d) {
    GstSample* sample = gst_app_sink_pull_sample(s);
    if (!sample) return GST_FLOW_OK;
    static_cast<VoiceTrack*>(d)->on_packet(gst_sample_get_buffer(sample));
    gst_sample_unref(sample);
    return GST_FLOW_OK;
  };
  gst_app_sink_set_callbacks(GST_APP_SINK(sink), &callbacks, this, nullptr);
  gst_bin_add(GST_BIN(pipeline), sink);
  gst_element_sync_state_with_parent(sink);
  GstPad* sink_pad = gst_element_get_static_pad(sink, "sink");
  gst_pad_link(pad, sink_pad);
  gst_object_unref(sink_pad);
}

void VoiceTrack::on_packet(GstBuffer* buffer) {
  if (!buffer) return;
  GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
  if (!gst_rtp_buffer_map(buffer, GST_MAP_READ, &rtp)) {
    std::lock_guard lock(mutex_);
    ++counters_.packets_refused;
    return;
  }
  ReceivedVoice voice;
  const uint16_t sequence = gst_rtp_buffer_get_seq(&rtp);
  voice.rtp_time = gst_rtp_buffer_get_timestamp(&rtp);
  const auto* payload = static_cast<const uint8_t*>(gst_rtp_buffer_get_payload(&rtp));
  voice.packet.assign(payload, payload + gst_rtp_buffer_get_payload_len(&rtp));
  gst_rtp_buffer_unmap(&rtp);
  std::lock_guard lock(mutex_);
  if (voice.packet.empty() || voice.packet.size() > kMaxOpusPacket) {
    ++counters_.packets_refused;
    return;
  }
  voice.sequence = sequences_.extend(sequence);
  // The jitter buffer hands packets out in order: a jump is what it gave up on.
  if (have_sequence_ && int32_t(voice.sequence - last_sequence_) > 1)
    counters_.packets_lost += uint32_t(voice.sequence - last_sequence_) - 1;
  if (!have_sequence_ || int32_t(voice.sequence - last_sequence_) > 0) last_sequence_ = voice.sequence;
  have_sequence_ = true;
  ++counters_.packets_received;
  received_.push_back(std::move(voice));
  while (received_.size() > kMaxReceivedPackets) {
    received_.pop_front();
    ++counters_.packets_dropped;
  }
}

std::vector<ReceivedVoice> VoiceTrack::take() {
  std::lock_guard lock(mutex_);
  std::vector<ReceivedVoice> out(std::make_move_iterator(received_.begin()), std::make_move_iterator(received_.end()));
  received_.clear();
  return out;
}

VoiceTrackCounters VoiceTrack::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

}  // namespace rt::media
