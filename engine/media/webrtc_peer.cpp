// The GStreamer side of the WebRTC link (webrtc_peer.h says what travels where). webrtcbin runs
// its own threads: signals arrive on them, so the shared state sits behind one mutex, and the
// callbacks never call back into webrtcbin while holding it.
#include "media/webrtc_peer.h"

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gst/rtp/gstrtpbuffer.h>
#include <gst/sdp/sdp.h>
#include <gst/video/video.h>
#include <gst/webrtc/webrtc.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "media/bitrate_follower.h"
#include "media/call_feedback.h"
#include "media/codec_probes.h"
#include "media/frame_time_sei.h"
#include "media/ice_servers.h"
#include "media/portrait_frame.h"
#include "media/portrait_pictures.h"
#include "media/webrtc_peer_impl.h"
#include "time/monotonic_clock.h"

namespace rt::media {
namespace {

constexpr size_t kMaxChannelMessage = 64 * 1024;  // the session's small messages are far below
constexpr size_t kMaxSdpBytes = 256 * 1024;
constexpr size_t kMaxPendingFrames = 16;  // RTP timestamps waiting for their other parts
constexpr const char* kFastLabel = "rt-fast";
constexpr const char* kReliableLabel = "rt-reliable";
// RTCP's pace decides whether retransmission works at all. Under AVPF a NACK (or a keyframe
// request) may go early, alone, only once between two regular reports; every later one waits for
// the next regular report. RTP spaces those by its share of the session's bandwidth, which
// rtpsession, left to guess, put so low that they went far past the jitter buffer's patience, so
// most NACKs expired unsent and a lost packet became a lost picture. Told the call's real
// bandwidth (its ceilings), RTCP's share allows a report at this floor, so a NACK waits at most
// about one floor, within the jitter buffer's patience, for a small share of the call's bits.
constexpr GstClockTime kRtcpInterval = 50 * GST_MSECOND;
// How long the jitter buffer waits for a missing packet (its retransmission) before giving it up.
// Only a gap waits: with the appsink not syncing, packets in order pass at once. A starved sender
// or receiver on a loaded machine delays everything in flight, retransmissions too, so the wait
// must cover that as well as the round trip (docs/webrtc.md has what shorter waits lost).
constexpr int kJitterBufferMs = 200;

void require_element(const char* name, const char* package) {
  GstElementFactory* factory = gst_element_factory_find(name);
  if (!factory)
    throw std::runtime_error(std::string("the WebRTC link needs the GStreamer element ") + name +
                             ", which is missing: apt-get install " + package);
  gst_object_unref(factory);
}

uint32_t rtp_time_of(GstClockTime pts) { return uint32_t(gst_util_uint64_scale_int(pts, 90000, GST_SECOND)); }
GstClockTime pts_of_rtp_time(uint64_t ticks) { return gst_util_uint64_scale_int_ceil(ticks, GST_SECOND, 90000); }

// How the depayloader hands pictures on: 0 for a byte stream, else AVC's NAL length size (from
// the codec data's fifth byte), as media/frame_time_sei.h reads them.
unsigned nal_length_size_of(GstPad* pad) {
  GstCaps* caps = gst_pad_get_current_caps(pad);
  const GstStructure* s = caps ? gst_caps_get_structure(caps, 0) : nullptr;
  const char* format = s ? gst_structure_get_string(s, "stream-format") : nullptr;
  unsigned size = 0;
  if (format && std::string(format) == "avc") {
    size = 4;
    const GValue* value = gst_structure_get_value(s, "codec_data");
    GstBuffer* codec_data = value && G_VALUE_HOLDS(value, GST_TYPE_BUFFER) ? gst_value_get_buffer(value) : nullptr;
    guint8 byte = 0;
    if (codec_data && gst_buffer_extract(codec_data, 4, &byte, 1) == 1) size = (byte & 3u) + 1;
  }
  if (caps) gst_caps_unref(caps);
  return size;
}

// Which channel a message type travels on: the fast one for what the next copy replaces anyway.
bool travels_fast(net::MessageType type) { return type == net::MessageType::Eye || type == net::MessageType::Skeleton; }

}  // namespace


void WebRtcPeer::Impl::maybe_offer() {
  bool ready = true;
  for (const char* name : {"sink_0", "sink_1", "sink_2"}) {
    GstPad* pad = gst_element_get_static_pad(webrtc, name);
    ready = ready && pad && gst_pad_has_current_caps(pad);
    if (pad) gst_object_unref(pad);
  }
  {
    std::lock_guard lock(mutex);
    if (!ready || offered || !options.offerer) return;
    offered = true;
  }
  ask_for_retransmission();
  GstPromise* promise = gst_promise_new_with_change_func(&Impl::on_offer_created, this, nullptr);
  g_signal_emit_by_name(webrtc, "create-offer", nullptr, promise);
}

void WebRtcPeer::Impl::ask_for_retransmission() {
  // The voice's transceiver: its pad's, or one of kind audio that the other peer's offer made.
  GstWebRTCRTPTransceiver* voice_transceiver = nullptr;
  if (GstPad* pad = gst_element_get_static_pad(webrtc, "sink_2")) {
    g_object_get(pad, "transceiver", &voice_transceiver, nullptr);
    gst_object_unref(pad);
  }
  GArray* transceivers = nullptr;
  g_signal_emit_by_name(webrtc, "get-transceivers", &transceivers);
  for (guint i = 0; transceivers && i < transceivers->len; ++i) {
    GstWebRTCRTPTransceiver* transceiver = g_array_index(transceivers, GstWebRTCRTPTransceiver*, i);
    GstWebRTCKind kind = GST_WEBRTC_KIND_UNKNOWN;
    g_object_get(transceiver, "kind", &kind, nullptr);
    const bool voice_track = transceiver == voice_transceiver || kind == GST_WEBRTC_KIND_AUDIO;
    g_object_set(transceiver, "do-nack", gboolean(voice_track ? options.voice_retransmit : options.retransmit), nullptr);
  }
  if (voice_transceiver) gst_object_unref(voice_transceiver);
  if (transceivers) g_array_unref(transceivers);
}

void WebRtcPeer::Impl::on_offer_created(GstPromise* promise, gpointer data) {
  auto* self = static_cast<Impl*>(data);
  GstWebRTCSessionDescription* offer = nullptr;
  if (gst_promise_wait(promise) == GST_PROMISE_RESULT_REPLIED) {
    const GstStructure* reply = gst_promise_get_reply(promise);
    if (reply) gst_structure_get(reply, "offer", GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &offer, nullptr);
  }
  gst_promise_unref(promise);
  if (!offer) return self->fail(self->options.name + ": webrtcbin made no offer");
  self->announce_local(offer, "offer");
  gst_webrtc_session_description_free(offer);
}

void WebRtcPeer::Impl::announce_local(GstWebRTCSessionDescription* description, const char* type) {
  g_signal_emit_by_name(webrtc, "set-local-description", description, nullptr);
  gchar* text = gst_sdp_message_as_text(description->sdp);
  const std::string sdp = text ? text : "";
  g_free(text);
  if (signalling.on_description) signalling.on_description(type, sdp);
}

void WebRtcPeer::Impl::adopt_channel(GstWebRTCDataChannel* channel) {
  gchar* label = nullptr;
  g_object_get(channel, "label", &label, nullptr);
  const std::string name = label ? label : "";
  g_free(label);
  GstWebRTCDataChannel** slot = name == kFastLabel ? &fast : name == kReliableLabel ? &reliable : nullptr;
  if (options.relayed && !options.offerer && name != kReliableLabel) slot = &relayed_in;
  if (!slot) return refuse(options.name + ": a data channel '" + name + "' this link does not use, ignored");
  {
    std::lock_guard lock(mutex);
    if (*slot) return;
    *slot = GST_WEBRTC_DATA_CHANNEL(gst_object_ref(channel));
  }
  g_signal_connect(channel, "on-message-data", G_CALLBACK(+[](GstWebRTCDataChannel* c, GBytes* b, gpointer d) {
                     static_cast<Impl*>(d)->on_channel_bytes(c, b);
                   }),
                   this);
  g_signal_connect(channel, "on-message-string", G_CALLBACK(+[](GstWebRTCDataChannel*, gchar*, gpointer d) {
                     static_cast<Impl*>(d)->refuse("a text message on a data channel: this link sends binary only");
                   }),
                   this);
}

void WebRtcPeer::Impl::on_channel_bytes(GstWebRTCDataChannel* channel, GBytes* bytes) {
  gsize size = 0;
  const auto* data = static_cast<const uint8_t*>(g_bytes_get_data(bytes, &size));
  if (size > kMaxChannelMessage)
    return refuse("a data-channel message of " + std::to_string(size) + " bytes, over the " +
                  std::to_string(kMaxChannelMessage) + " this link accepts");
  std::span<const uint8_t> view(data, size);
  bool on_fast = false, relayed_channel = false;
  {
    std::lock_guard lock(mutex);  // adopt_channel sets `fast` from another thread
    on_fast = channel == fast;
    relayed_channel = channel == relayed_in;
  }
  ChannelGuard::Received opened;
  if (options.guard) {
    opened = options.guard->receive(on_fast ? GuardedChannel::Fast : GuardedChannel::Reliable, view);
    if (opened.kind == ChannelGuard::Received::Kind::Refused) {
      if (!opened.reply.empty()) send_handshake_frame(opened.reply);
      return refuse(options.name + ": " + opened.reason);
    }
    if (opened.kind == ChannelGuard::Received::Kind::Early) {
      std::lock_guard lock(mutex);
      ++counters.messages_early;
      return;
    }
    if (opened.kind == ChannelGuard::Received::Kind::Handshake) {
      if (!opened.reply.empty()) send_handshake_frame(opened.reply);
      return;
    }
    view = opened.message;
  }
  if (is_portrait_frame(view)) {
    std::string why;
    auto frame = decode_portrait_frame(view, options.width, options.height, &why);
    if (!frame || !(on_fast || relayed_channel)) return refuse(frame ? "a portrait frame record on the reliable channel" : why);
    return store_part(frame->rtp_timestamp, nullptr, nullptr, std::move(frame));
  }
  net::DecodeResult result = net::decode_message(view);
  if (!result.ok()) return refuse("a data-channel message refused: " + result.error.message);
  const net::MessageType type = net::message_type(*result.message);
  if (type == net::MessageType::Portrait) return refuse("a portrait on a data channel: portraits travel as video");
  if (type == net::MessageType::Signal) return refuse("a signal on a data channel: signals set the call up beside it");
  if (type == net::MessageType::Voice && !relayed_channel)
    return refuse("a voice frame on a data channel: the voice travels as an audio track");
  if (!relayed_channel && travels_fast(type) != on_fast)
    return refuse(std::string("a ") + net::message_type_name(type) + " message on the wrong data channel");
  std::lock_guard lock(mutex);
  ++counters.messages_received;
  messages.push_back(std::move(*result.message));
}

void WebRtcPeer::Impl::on_element_added(GstElement* element) {
  GstElementFactory* factory = gst_element_get_factory(element);
  if (!factory) return;
  const std::string kind = GST_OBJECT_NAME(factory);
  if (kind == "rtpsession") {
    // The property says bytes a second; rtpsession computes with it as bits a second (given as
    // bytes, the reports stayed too far apart for the floor to hold).
    const double bits_per_second = 1000.0 * (std::max(options.color_kbps, options.color_ceiling_kbps) + options.depth_kbps);
    g_object_set(element, "rtcp-min-interval", guint64(kRtcpInterval), "bandwidth", bits_per_second, nullptr);
  } else {
    if (kind == "rtpjitterbuffer") watch_jitter_buffer_for_voice(element, options.voice_jitter_buffer_ms);
    retransmission.watch(element);
  }
}

void WebRtcPeer::Impl::link_incoming(GstPad* pad) {
  if (GST_PAD_DIRECTION(pad) != GST_PAD_SRC) return;
  GstCaps* caps = gst_pad_get_current_caps(pad);
  const GstStructure* s = caps ? gst_caps_get_structure(caps, 0) : nullptr;
  const char* encoding = s ? gst_structure_get_string(s, "encoding-name") : nullptr;
  const bool h264 = encoding && std::string(encoding) == "H264";
  int payload = 0;
  if (s) gst_structure_get_int(s, "payload", &payload);
  if (caps) gst_caps_unref(caps);
  if (encoding && std::string(encoding) == "OPUS") return voice.link_incoming(pipeline, pad);
  // Every incoming pad gets linked: an unlinked one tears the whole bundle down.
  if (!h264) {
    GstElement* sink = gst_element_factory_make("fakesink", nullptr);
    gst_bin_add(GST_BIN(pipeline), sink);
    gst_element_sync_state_with_parent(sink);
    GstPad* sink_pad = gst_element_get_static_pad(sink, "sink");
    gst_pad_link(pad, sink_pad);
    gst_object_unref(sink_pad);
    return refuse(options.name + ": an incoming stream that is not H.264, discarded");
  }
  auto chain = std::make_unique<IncomingChain>();
  chain->impl = this;
  chain->color = payload == 96;
  GstElement* depay = gst_element_factory_make("rtph264depay", nullptr);
  GstElement* decoder = gst_element_factory_make("avdec_h264", nullptr);
  GstElement* sink = gst_element_factory_make("appsink", nullptr);
  // Off by default: without it a lost picture stays broken until the next periodic keyframe.
  g_object_set(depay, "request-keyframe", TRUE, "wait-for-keyframe", TRUE, nullptr);
  // Slice threads, not frame threads: frame threading holds frames back, a frame per thread.
  gst_util_set_object_arg(G_OBJECT(decoder), "thread-type", "slice");
  g_object_set(sink, "sync", FALSE, "max-buffers", 8u, "drop", FALSE, nullptr);
  GstAppSinkCallbacks callbacks{};
  callbacks.new_sample = +[](GstAppSink* s, gpointer d) {
    auto* c = static_cast<IncomingChain*>(d);
    c->impl->on_sample(s, *c);
    return GST_FLOW_OK;
  };
  gst_app_sink_set_callbacks(GST_APP_SINK(sink), &callbacks, chain.get(), nullptr);
  gst_bin_add_many(GST_BIN(pipeline), depay, decoder, sink, nullptr);
  gst_element_link_many(depay, decoder, sink, nullptr);

  // The RTP time of each packet going in, by its presentation time; the depayloaded picture takes
  // it as its own presentation time, which the decoder keeps: the appsink reads it back. The time
  // a picture carries in its bitstream wins: an SFU may have rewritten the header's.
  GstPad* depay_sink = gst_element_get_static_pad(depay, "sink");
  gst_pad_add_probe(depay_sink, GST_PAD_PROBE_TYPE_BUFFER, +[](GstPad* pad, GstPadProbeInfo* info, gpointer d) {
                      auto* c = static_cast<IncomingChain*>(d);
                      GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
                      GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
                      if (gst_rtp_buffer_map(buffer, GST_MAP_READ, &rtp)) {
                        c->last_rtp = gst_rtp_buffer_get_timestamp(&rtp);
                        c->losses.on_packet(gst_rtp_buffer_get_seq(&rtp));
                        if (c->stalled.on_packet(c->last_rtp, monotonic_now_us()))
                          // Upstream from the depayloader: RTCP carries it to the sender as a PLI.
                          gst_pad_push_event(pad, gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
                        c->pts_to_rtp[c->next++ % c->pts_to_rtp.size()] = {GST_BUFFER_PTS(buffer), c->last_rtp};
                        gst_rtp_buffer_unmap(&rtp);
                      }
                      return GST_PAD_PROBE_OK;
                    },
                    chain.get(), nullptr);
  gst_object_unref(depay_sink);
  GstPad* depay_src = gst_element_get_static_pad(depay, "src");
  gst_pad_add_probe(depay_src, GST_PAD_PROBE_TYPE_BUFFER, +[](GstPad* pad, GstPadProbeInfo* info, gpointer d) {
                      auto* c = static_cast<IncomingChain*>(d);
                      GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
                      uint32_t rtp = c->last_rtp;
                      for (size_t i = 0; i < c->pts_to_rtp.size(); ++i) {
                        const auto& [pts, ts] = c->pts_to_rtp[(c->next + c->pts_to_rtp.size() - 1 - i) % c->pts_to_rtp.size()];
                        if (pts == GST_BUFFER_PTS(buffer)) {
                          rtp = ts;
                          break;
                        }
                      }
                      // The header's time, moved to the sender's: an SFU shifts a stream's times
                      // by one amount from the packet it relayed first. Not every buffer carries
                      // the time (the depayloader may hand a picture on in parts).
                      if (const std::optional<uint32_t> carried = c->frame_time.frame_time_of(buffer, nal_length_size_of(pad)))
                        c->sender_minus_header = *carried - rtp;
                      rtp += c->sender_minus_header;
                      buffer = gst_buffer_make_writable(buffer);
                      GST_BUFFER_PTS(buffer) = pts_of_rtp_time(rtp);
                      GST_BUFFER_DTS(buffer) = GST_CLOCK_TIME_NONE;
                      GST_PAD_PROBE_INFO_DATA(info) = buffer;
                      return GST_PAD_PROBE_OK;
                    },
                    chain.get(), nullptr);
  gst_object_unref(depay_src);
  chain->decode.attach(decoder);
  GstPad* asking = gst_element_get_static_pad(depay, "sink");
  chain->asked.attach(asking);
  gst_object_unref(asking);
  for (GstElement* e : {depay, decoder, sink}) gst_element_sync_state_with_parent(e);
  GstPad* depay_pad = gst_element_get_static_pad(depay, "sink");
  const GstPadLinkReturn linked = gst_pad_link(pad, depay_pad);
  gst_object_unref(depay_pad);
  if (linked != GST_PAD_LINK_OK) fail(options.name + ": could not link an incoming video stream");
  std::lock_guard lock(mutex);
  chains.push_back(std::move(chain));
}

void WebRtcPeer::Impl::on_sample(GstAppSink* sink, IncomingChain& chain) {
  GstSample* sample = gst_app_sink_pull_sample(sink);
  if (!sample) return;
  chain.losses.on_picture();
  chain.stalled.on_picture();
  GstVideoInfo info;
  GstCaps* caps = gst_sample_get_caps(sample);
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  if (!caps || !buffer || !gst_video_info_from_caps(&info, caps)) {
    gst_sample_unref(sample);
    return fail(options.name + ": a decoded frame without video caps");
  }
  const uint32_t w = options.width, h = options.height;
  const GstVideoFormat format = GST_VIDEO_INFO_FORMAT(&info);
  // A picture smaller than the call's is the sender's size stepped down: scaled back here.
  std::string why = check_received_picture_size(GST_VIDEO_INFO_WIDTH(&info), GST_VIDEO_INFO_HEIGHT(&info), w, h);
  if (why.empty() && format != GST_VIDEO_FORMAT_I420 && format != GST_VIDEO_FORMAT_Y444_10LE)
    why = std::string("a decoded frame in ") + gst_video_format_to_string(format) + ", the link carries I420 and Y444_10LE";
  if (!why.empty()) {
    gst_sample_unref(sample);
    std::lock_guard lock(mutex);
    ++counters.frames_unpaired;
    last_error = options.name + ": " + why;
    return;
  }
  GstVideoFrame frame;
  if (!gst_video_frame_map(&frame, &info, buffer, GST_MAP_READ)) {
    gst_sample_unref(sample);
    return fail(options.name + ": a decoded frame could not be mapped");
  }
  chain.color = format == GST_VIDEO_FORMAT_I420;
  const uint32_t rtp = rtp_time_of(GST_BUFFER_PTS(buffer));
  const bool scaled = uint32_t(GST_VIDEO_INFO_WIDTH(&info)) != w || uint32_t(GST_VIDEO_INFO_HEIGHT(&info)) != h;
  if (format == GST_VIDEO_FORMAT_I420) {
    std::vector<uint8_t> rgb = rgb_of_color_picture(frame, w, h);
    gst_video_frame_unmap(&frame);
    gst_sample_unref(sample);
    store_part(rtp, &rgb, nullptr, std::nullopt, scaled);
  } else {
    DepthAlphaCodes codes = codes_of_depth_alpha_picture(frame, w, h);
    gst_video_frame_unmap(&frame);
    gst_sample_unref(sample);
    store_part(rtp, nullptr, &codes, std::nullopt, scaled);
  }
}

void WebRtcPeer::Impl::store_part(uint32_t rtp, std::vector<uint8_t>* rgb, DepthAlphaCodes* codes,
                                  std::optional<PortraitFrame> frame, bool scaled) {
  std::lock_guard lock(mutex);
  if (scaled) ++(rgb ? counters.color_pictures_scaled : counters.depth_pictures_scaled);
  auto [it, inserted] = pending.try_emplace(rtp);
  if (inserted) it->second.order = pending_order++;
  if (rgb) it->second.rgb = std::move(*rgb);
  if (codes) it->second.codes = std::move(*codes);
  if (frame) {
    it->second.frame = *frame;
    it->second.has_frame = true;
  }
  if (!it->second.rgb.empty() && !it->second.codes.luma.empty() && it->second.has_frame) {
    // Paired. The conversion to float images (milliseconds at 720p) waits for take_portrait, on
    // the taker's thread: here it would hold up this track's decoding.
    it->second.order = monotonic_now_us();
    ++counters.portraits_received;
    paired.push_back(std::move(it->second));
    pending.erase(it);
    while (paired.size() > options.max_queued_portraits) {
      paired.pop_front();
      ++counters.portraits_dropped;
    }
    return;
  }
  while (pending.size() > kMaxPendingFrames) {
    auto oldest = std::min_element(pending.begin(), pending.end(),
                                   [](const auto& a, const auto& b) { return a.second.order < b.second.order; });
    counters.frames_unpaired += (oldest->second.rgb.empty() ? 0 : 1) + (oldest->second.codes.luma.empty() ? 0 : 1) +
                                (oldest->second.has_frame ? 1 : 0);
    if (oldest->second.has_frame) {
      ++counters.portraits_lost;
      counters.color_loss.frames_lost += oldest->second.rgb.empty() ? 1 : 0;
      counters.depth_loss.frames_lost += oldest->second.codes.luma.empty() ? 1 : 0;
    }
    pending.erase(oldest);
  }
}

ReceivedPortrait WebRtcPeer::Impl::assemble(PendingFrame part) {
  ReceivedPortrait received;
  received.rtp_timestamp = part.frame.rtp_timestamp;
  received.portrait = portrait_of_planes(part.frame, part.rgb, part.codes);
  received.received_us = part.order;
  return received;
}

WebRtcPeer::WebRtcPeer(WebRtcPeerOptions options, Signalling signalling) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = std::move(options);
  m.signalling = std::move(signalling);
  const WebRtcPeerOptions& o = m.options;
  if (o.width == 0 || o.height == 0 || o.width % 2 || o.height % 2 || o.width > 4096 || o.height > 4096)
    throw std::runtime_error("the WebRTC link carries even sizes up to 4096x4096, not " + std::to_string(o.width) + "x" +
                             std::to_string(o.height));
  if (o.fps < 1 || o.fps > 240 || o.color_kbps < 100 || o.depth_kbps < 100 || o.keyframe_interval < 1 ||
      o.depth_quality < 0 || o.depth_quality > 50)
    throw std::runtime_error("the WebRTC link's rate, bitrates (>= 100 kbit/s), depth quality (0..50) or keyframe interval are out of range");
  if (const std::string why = check_depth_range(o.depth_range); !why.empty()) throw std::runtime_error(why);
  if (o.voice_jitter_buffer_ms < 1 || o.voice_jitter_buffer_ms > 1000)
    throw std::runtime_error("the voice's jitter buffer waits 1..1000 ms, not " + std::to_string(o.voice_jitter_buffer_ms));
  const BitrateRuleOptions color_rate{.start_kbps = o.color_kbps, .floor_kbps = o.color_floor_kbps, .ceiling_kbps = o.color_ceiling_kbps};
  if (const std::string why = check_bitrate_rule(color_rate); !why.empty()) throw std::runtime_error("colour: " + why);
  if (!(o.simulated_loss <= 1.0))
    throw std::runtime_error("the simulated network's loss must be a fraction between 0 and 1, not " + std::to_string(o.simulated_loss));
  static std::once_flag once;
  std::call_once(once, [] { gst_init(nullptr, nullptr); });
  require_element("webrtcbin", "gstreamer1.0-plugins-bad");
  require_element("dtlsenc", "gstreamer1.0-plugins-bad");
  require_element("sctpenc", "gstreamer1.0-plugins-bad");
  require_element("nicesrc", "gstreamer1.0-nice");
  require_element("x264enc", "gstreamer1.0-plugins-ugly");
  require_element("rtph264pay", "gstreamer1.0-plugins-good");
  require_element("avdec_h264", "gstreamer1.0-libav");
  require_element("rtpopuspay", "gstreamer1.0-plugins-good");
  require_element("appsrc", "gstreamer1.0-plugins-base");
  if (o.simulated_loss >= 0) require_element("netsim", "gstreamer1.0-plugins-bad");

  const std::string size = "width=" + std::to_string(o.width) + ",height=" + std::to_string(o.height) +
                           ",framerate=" + std::to_string(o.fps) + "/1";
  // zerolatency: no lookahead, no B-frames, sliced threads. psy-tune=psnr: the psychovisual tricks
  // that trade fidelity for perceived detail would move depth. ultrafast: 720p colour and 10-bit
  // depth each encode in 5-8 ms on one of CI's cores. Colour runs at its target bitrate; depth at a
  // constant quality (x264's CRF), its bitrate a ceiling: with a bitrate target a keyframe's depth
  // erred by 2.7 mm (median over the user), at quality 14 no frame errs by more than 1.4 mm
  // (640x360, tests/test_media_webrtc.cpp). The depth track is 4:4:4 so that its first chroma plane
  // carries the alpha matte's soft edge at full resolution (media/depth_alpha_codec.h; at half
  // resolution a tiny portrait's hand came back far worse than over the direct session); its chroma
  // is quantized coarser than the depth (chroma-qp-offset, at its limit): the matte needs a few
  // hundred levels, not the depth's precision, and at the luma's quantizer it cost bits for nothing.
  // Both payloaders start their RTP time at 0
  // (timestamp-offset), so a portrait's two frames carry one RTP timestamp.
  const auto track = [&](const char* name, const char* format, const char* profile, const char* preset, int kbps, int pt,
                         const std::string& rate) {
    return std::string("appsrc name=") + name + "src is-live=true format=time do-timestamp=false caps=video/x-raw,format=" +
           format + "," + size + " ! x264enc name=" + name + "enc tune=zerolatency speed-preset=" + preset +
           " psy-tune=psnr bframes=0 key-int-max=" +
           std::to_string(o.keyframe_interval) + " bitrate=" + std::to_string(kbps) + rate +
           " ! video/x-h264,stream-format=byte-stream,alignment=au,profile=" + profile + " ! rtph264pay name=" + name + "pay config-interval=-1 aggregate-mode=zero-latency timestamp-offset=0 pt=" +
           std::to_string(pt) + " mtu=1200 ! application/x-rtp,media=video,encoding-name=H264,clock-rate=90000,payload=" +
           std::to_string(pt) + " ! webrtc.";
  };
  const std::string description = "webrtcbin name=webrtc bundle-policy=max-bundle latency=" + std::to_string(kJitterBufferMs) + " " +
                                  track("color", "I420", "high", "ultrafast", o.color_kbps, 96, "") + " " +
                                  track("depth", "Y444_10LE", "high-4:4:4", "ultrafast", o.depth_kbps, 97,
                                        " pass=qual quantizer=" + std::to_string(o.depth_quality) + " option-string=chroma-qp-offset=12") + " " +
                                  voice_track_description();
  GError* error = nullptr;
  m.pipeline = gst_parse_launch(description.c_str(), &error);
  if (!m.pipeline || error) {
    const std::string why = error ? error->message : "unknown";
    if (error) g_error_free(error);
    if (m.pipeline) gst_object_unref(m.pipeline);
    m.pipeline = nullptr;
    throw std::runtime_error("the WebRTC pipeline could not be made: " + why);
  }
  // The pipeline's running time is the site's monotonic clock (GStreamer's system clock, with no base
  // time taken off): a voice packet's presentation time is its capture time, which its RTP time
  // carries to the other site.
  GstClock* system_clock = gst_system_clock_obtain();
  gst_pipeline_use_clock(GST_PIPELINE(m.pipeline), system_clock);
  gst_object_unref(system_clock);
  gst_element_set_start_time(m.pipeline, GST_CLOCK_TIME_NONE);
  gst_element_set_base_time(m.pipeline, 0);
  m.webrtc = gst_bin_get_by_name(GST_BIN(m.pipeline), "webrtc");
  m.color_src = gst_bin_get_by_name(GST_BIN(m.pipeline), "colorsrc");
  m.depth_src = gst_bin_get_by_name(GST_BIN(m.pipeline), "depthsrc");
  m.color_enc = gst_bin_get_by_name(GST_BIN(m.pipeline), "colorenc");
  m.depth_enc = gst_bin_get_by_name(GST_BIN(m.pipeline), "depthenc");
  if (m.color_enc && m.depth_enc) {
    m.color_encode.attach(m.color_enc);
    m.depth_encode.attach(m.depth_enc);
    for (GstElement* encoder : {m.color_enc, m.depth_enc}) {
      GstPad* src = gst_element_get_static_pad(encoder, "src");
      m.asked_of_us.attach(src);
      // Each picture carries its RTP time, as the payloader makes it: from its running time (the
      // encoder shifts presentation times by a segment of its own to keep decoding times positive).
      gst_pad_add_probe(src, GST_PAD_PROBE_TYPE_BUFFER, +[](GstPad* pad, GstPadProbeInfo* info, gpointer d) {
                          GstBuffer* picture = GST_PAD_PROBE_INFO_BUFFER(info);
                          GstEvent* event = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0);
                          const GstSegment* segment = nullptr;
                          if (event) gst_event_parse_segment(event, &segment);
                          const GstClockTime running =
                              segment ? gst_segment_to_running_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(picture)) : GST_CLOCK_TIME_NONE;
                          if (event) gst_event_unref(event);
                          if (!GST_CLOCK_TIME_IS_VALID(running)) return GST_PAD_PROBE_OK;
                          if (GstBuffer* stamped = static_cast<FrameTimeSei*>(d)->with_frame_time(picture, rtp_time_of(running))) {
                            gst_buffer_unref(picture);
                            GST_PAD_PROBE_INFO_DATA(info) = stamped;
                          }
                          return GST_PAD_PROBE_OK;
                        },
                        encoder == m.color_enc ? &m.color_frame_time : &m.depth_frame_time, nullptr);
      gst_object_unref(src);
    }
  }
  m.sent_width = o.width;
  m.sent_height = o.height;

  configure_ice(m.webrtc, o.stun_server, o.turn_server, o.relay_only, o.local_addresses);

  // Encoded bytes per track, as RTP packets leave the payloaders (a fragmented picture leaves as
  // a buffer list).
  for (const char* name : {"colorpay", "depthpay"}) {
    GstElement* pay = gst_bin_get_by_name(GST_BIN(m.pipeline), name);
    GstPad* src = gst_element_get_static_pad(pay, "src");
    uint64_t* total = std::string(name) == "colorpay" ? &m.counters.color_bytes_sent : &m.counters.depth_bytes_sent;
    m.byte_counts.push_back({&m, total});
    gst_pad_add_probe(src, GstPadProbeType(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST),
                      +[](GstPad*, GstPadProbeInfo* info, gpointer d) {
                        auto* count = static_cast<ByteCount*>(d);
                        const size_t bytes = (info->type & GST_PAD_PROBE_TYPE_BUFFER_LIST)
                                                 ? gst_buffer_list_calculate_size(GST_PAD_PROBE_INFO_BUFFER_LIST(info))
                                                 : gst_buffer_get_size(GST_PAD_PROBE_INFO_BUFFER(info));
                        std::lock_guard lock(count->impl->mutex);
                        *count->total += bytes;
                        return GST_PAD_PROBE_OK;
                      },
                      &m.byte_counts.back(), nullptr);
    gst_object_unref(src);
    gst_object_unref(pay);
  }

  if (o.simulated_loss >= 0)
    // webrtcbin puts the element it is given between its RTP session (retransmissions included)
    // and the network: the loss is the network's, which NACK can repair, not the encoder's.
    g_signal_connect(m.webrtc, "request-aux-sender", G_CALLBACK(+[](GstElement*, GObject*, gpointer d) -> GstElement* {
                       auto* impl = static_cast<Impl*>(d);
                       GstElement* netsim = gst_element_factory_make("netsim", nullptr);
                       if (!netsim) return nullptr;
                       g_object_set(netsim, "drop-probability", gfloat(impl->options.simulated_loss), nullptr);
                       std::lock_guard lock(impl->mutex);
                       if (!impl->netsim) impl->netsim = GST_ELEMENT(gst_object_ref(netsim));
                       return netsim;
                     }),
                     &m);
  g_signal_connect(m.pipeline, "deep-element-added", G_CALLBACK(+[](GstBin*, GstBin*, GstElement* element, gpointer d) {
                     static_cast<Impl*>(d)->on_element_added(element);
                   }),
                   &m);
  g_signal_connect(m.webrtc, "on-ice-candidate", G_CALLBACK(+[](GstElement*, guint mline, gchar* candidate, gpointer d) {
                     auto* impl = static_cast<Impl*>(d);
                     if (impl->signalling.on_candidate) impl->signalling.on_candidate(mline, candidate);
                   }),
                   &m);
  g_signal_connect(m.webrtc, "pad-added", G_CALLBACK(+[](GstElement*, GstPad* pad, gpointer d) {
                     static_cast<Impl*>(d)->link_incoming(pad);
                   }),
                   &m);
  g_signal_connect(m.webrtc, "on-data-channel", G_CALLBACK(+[](GstElement*, GstWebRTCDataChannel* channel, gpointer d) {
                     static_cast<Impl*>(d)->adopt_channel(channel);
                   }),
                   &m);
  // create-offer before both tracks have caps yields an offer without their media: wait for them.
  for (const char* pad_name : {"sink_0", "sink_1", "sink_2"}) {
    GstPad* pad = gst_element_get_static_pad(m.webrtc, pad_name);
    if (!pad) throw std::runtime_error(std::string("webrtcbin has no ") + pad_name);
    g_signal_connect(pad, "notify::caps", G_CALLBACK(+[](GObject*, GParamSpec*, gpointer d) {
                       static_cast<Impl*>(d)->maybe_offer();
                     }),
                     &m);
    gst_object_unref(pad);
  }
  GstBus* bus = gst_element_get_bus(m.pipeline);
  gst_bus_set_sync_handler(bus, +[](GstBus*, GstMessage* message, gpointer d) {
                             if (GST_MESSAGE_TYPE(message) == GST_MESSAGE_ERROR) {
                               GError* e = nullptr;
                               gst_message_parse_error(message, &e, nullptr);
                               static_cast<Impl*>(d)->fail(std::string("GStreamer: ") + (e ? e->message : "error"));
                               if (e) g_error_free(e);
                             }
                             return GST_BUS_DROP;
                           },
                           &m, nullptr);
  gst_object_unref(bus);

  if (gst_element_set_state(m.pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("the WebRTC pipeline would not start: " + last_error());
  m.voice.attach_sender(m.pipeline, o.voice_retransmit);
  m.bitrate = std::make_unique<BitrateFollower>(m.webrtc, m.color_enc, m.depth_enc, color_rate, o.depth_kbps, o.adapt_bitrate,
                                                o.step_portrait_size);
  if (o.offerer) m.open_channels();
}

void WebRtcPeer::Impl::open_channels() {
  GstWebRTCDataChannel* channel = nullptr;
  if (!options.relayed) {
    // Unordered without retransmits: a skeleton or an eye late is a skeleton or an eye stale.
    GstStructure* config = gst_structure_new("config", "ordered", G_TYPE_BOOLEAN, FALSE, "max-retransmits", G_TYPE_INT, 0, nullptr);
    g_signal_emit_by_name(webrtc, "create-data-channel", kFastLabel, config, &channel);
    gst_structure_free(config);
    if (channel) adopt_channel(channel), gst_object_unref(channel);
    channel = nullptr;
  }
  GstStructure* config = gst_structure_new("config", "ordered", G_TYPE_BOOLEAN, TRUE, nullptr);
  g_signal_emit_by_name(webrtc, "create-data-channel", kReliableLabel, config, &channel);
  gst_structure_free(config);
  if (channel) adopt_channel(channel), gst_object_unref(channel);
  if ((!options.relayed && !fast) || !reliable)
    throw std::runtime_error("webrtcbin made no data channel (gstreamer1.0-plugins-bad's sctp)");
}

WebRtcPeer::~WebRtcPeer() = default;

std::string WebRtcPeer::set_remote_description(const std::string& type, const std::string& sdp) {
  Impl& m = *impl_;
  const bool offer = type == "offer";
  if (!offer && type != "answer") return "a session description of type '" + type + "': expected offer or answer";
  if (offer == m.options.offerer)
    return offer ? "an offer given to the peer that makes the offer" : "an answer given to the peer that answers";
  if (sdp.size() > kMaxSdpBytes) return "a session description of " + std::to_string(sdp.size()) + " bytes, over the limit";
  // The SDP parser accepts nearly anything: a description this link can use starts with its
  // version line and has media.
  GstSDPMessage* message = nullptr;
  gst_sdp_message_new(&message);
  if (sdp.rfind("v=0", 0) != 0 || gst_sdp_message_parse_buffer(reinterpret_cast<const guint8*>(sdp.data()), guint(sdp.size()),
                                                               message) != GST_SDP_OK ||
      gst_sdp_message_medias_len(message) == 0) {
    gst_sdp_message_free(message);
    return "a malformed session description (no 'v=0' line or no media)";
  }
  GstWebRTCSessionDescription* description =
      gst_webrtc_session_description_new(offer ? GST_WEBRTC_SDP_TYPE_OFFER : GST_WEBRTC_SDP_TYPE_ANSWER, message);
  GstPromise* promise = gst_promise_new();
  g_signal_emit_by_name(m.webrtc, "set-remote-description", description, promise);
  std::string why;
  if (gst_promise_wait(promise) != GST_PROMISE_RESULT_REPLIED) why = "webrtcbin did not take the description";
  else if (const GstStructure* reply = gst_promise_get_reply(promise); reply && gst_structure_has_field(reply, "error")) {
    GError* e = nullptr;
    gst_structure_get(reply, "error", G_TYPE_ERROR, &e, nullptr);
    why = std::string("webrtcbin refused the description: ") + (e ? e->message : "no reason given");
    if (e) g_error_free(e);
  }
  gst_promise_unref(promise);
  gst_webrtc_session_description_free(description);
  if (!why.empty() || !offer) return why;
  m.ask_for_retransmission();

  promise = gst_promise_new();
  g_signal_emit_by_name(m.webrtc, "create-answer", nullptr, promise);
  GstWebRTCSessionDescription* answer = nullptr;
  if (gst_promise_wait(promise) == GST_PROMISE_RESULT_REPLIED)
    if (const GstStructure* reply = gst_promise_get_reply(promise))
      gst_structure_get(reply, "answer", GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &answer, nullptr);
  gst_promise_unref(promise);
  if (!answer) return "webrtcbin made no answer to the offer";
  m.announce_local(answer, "answer");
  gst_webrtc_session_description_free(answer);
  if (m.options.relayed) {
    try {
      m.open_channels();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
  }
  return {};
}

void WebRtcPeer::add_ice_candidate(unsigned mline, const std::string& candidate) {
  g_signal_emit_by_name(impl_->webrtc, "add-ice-candidate", mline, candidate.c_str());
}

bool WebRtcPeer::Impl::channels_open() const {
  GstWebRTCICEConnectionState ice = GST_WEBRTC_ICE_CONNECTION_STATE_NEW;
  g_object_get(webrtc, "ice-connection-state", &ice, nullptr);
  if (ice != GST_WEBRTC_ICE_CONNECTION_STATE_CONNECTED && ice != GST_WEBRTC_ICE_CONNECTION_STATE_COMPLETED) return false;
  std::lock_guard lock(mutex);
  for (GstWebRTCDataChannel* channel : {fast, reliable}) {
    if (options.relayed && channel == fast) continue;
    if (!channel) return false;
    GstWebRTCDataChannelState state = GST_WEBRTC_DATA_CHANNEL_STATE_CLOSED;
    g_object_get(channel, "ready-state", &state, nullptr);
    if (state != GST_WEBRTC_DATA_CHANNEL_STATE_OPEN) return false;
  }
  return true;
}

bool WebRtcPeer::channels_up() const { return impl_->channels_open(); }

bool WebRtcPeer::connected() const {
  const Impl& m = *impl_;
  if (!m.channels_open()) return false;
  if (!m.options.guard) return true;
  // The connector's hello goes once both channels are open, again until answered (the guard says when).
  if (const std::vector<uint8_t> hello = m.options.guard->start(); !hello.empty())
    const_cast<Impl&>(m).send_handshake_frame(hello);
  return m.options.guard->ready();
}

bool WebRtcPeer::wait_connected(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!connected()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

void WebRtcPeer::send_portrait(const net::PortraitMessage& portrait) {
  Impl& m = *impl_;
  const uint32_t w = m.options.width, h = m.options.height;
  if (portrait.width != w || portrait.height != h || portrait.color.width != w || portrait.color.height != h ||
      portrait.depth.width != w || portrait.depth.height != h || portrait.color.format != PixelFormat::RGBA32F ||
      portrait.depth.format != PixelFormat::R32F)
    throw std::invalid_argument("a portrait of " + std::to_string(portrait.width) + "x" + std::to_string(portrait.height) +
                                " (or images of another size or format): this link carries " + std::to_string(w) + "x" +
                                std::to_string(h) + " RGBA32F colour and R32F depth");
  // One presentation time for both tracks, on whole RTP ticks, at least a millisecond after the
  // last, so that each portrait has its own RTP timestamp.
  GstClock* clock = gst_element_get_clock(m.pipeline);
  GstClockTime now = clock ? gst_clock_get_time(clock) - gst_element_get_base_time(m.pipeline) : 0;
  if (clock) gst_object_unref(clock);
  GstClockTime pts;
  {
    std::lock_guard lock(m.mutex);
    if (m.sent_any && now < m.last_pts + GST_MSECOND) now = m.last_pts + GST_MSECOND;
    pts = pts_of_rtp_time(gst_util_uint64_scale_int(now, 90000, GST_SECOND));
    m.last_pts = pts;
    m.sent_any = true;
  }
  PortraitFrame frame;
  frame.rtp_timestamp = rtp_time_of(pts);
  frame.frame_index = portrait.frame_index;
  frame.capture_timestamp_us = portrait.capture_timestamp_us;
  frame.width = w;
  frame.height = h;
  frame.fx = portrait.fx;
  frame.fy = portrait.fy;
  frame.cx = portrait.cx;
  frame.cy = portrait.cy;
  frame.camera_from_site = portrait.camera_from_site;
  frame.depth_range = m.options.depth_range;
  const std::vector<uint8_t> record = encode_portrait_frame(frame);
  std::string why;
  if (!decode_portrait_frame(record, w, h, &why)) throw std::invalid_argument("a portrait the receiver would refuse: " + why);

  // Both pictures at the size the path carries now (media/portrait_size_rule.h), changed together.
  const int step = m.bitrate ? m.bitrate->state().portrait_step : 0;
  const auto [sent_width, sent_height] = portrait_size_at_step(w, h, step);
  if (sent_width != m.sent_width || sent_height != m.sent_height) {
    for (GstElement* src : {m.color_src, m.depth_src}) set_picture_size(src, sent_width, sent_height);
    std::lock_guard lock(m.mutex);
    m.sent_width = sent_width;
    m.sent_height = sent_height;
  }
  GstBuffer* color = make_color_picture(portrait.color, sent_width, sent_height);
  GstBuffer* depth = make_depth_alpha_picture(portrait.color, portrait.depth, m.options.depth_range, sent_width, sent_height);

  const GstClockTime duration = GST_SECOND / GstClockTime(m.options.fps);
  for (GstBuffer* b : {color, depth}) {
    GST_BUFFER_PTS(b) = pts;
    GST_BUFFER_DURATION(b) = duration;
  }
  // The record first: it is small and usually arrives before the pictures it describes.
  {
    std::lock_guard lock(m.mutex);
    ++m.counters.portraits_sent;
  }
  // Before the channel opens (the first portrait, which lets the offer be made) the record has
  // nowhere to go; the pictures are dropped by webrtcbin then too.
  send_raw(Channel::Fast, record);
  gst_app_src_push_buffer(GST_APP_SRC(m.color_src), color);
  gst_app_src_push_buffer(GST_APP_SRC(m.depth_src), depth);
}

bool WebRtcPeer::send_message(const net::Message& message) {
  const net::MessageType type = net::message_type(message);
  if (type == net::MessageType::Portrait)
    throw std::invalid_argument("a portrait goes through send_portrait: it travels as video");
  if (type == net::MessageType::Signal)
    throw std::invalid_argument("a signal goes to the other site beside the call, not on its data channels");
  if (type == net::MessageType::Voice && !impl_->options.relayed)
    throw std::invalid_argument("a voice frame goes through send_voice: it travels as an audio track");
  const std::vector<uint8_t> bytes = net::encode_message(message);
  if (bytes.size() > kMaxChannelMessage) throw std::invalid_argument("a message over the data channels' limit");
  if (!send_raw(travels_fast(type) ? Channel::Fast : Channel::Reliable, bytes)) return false;
  std::lock_guard lock(impl_->mutex);
  ++impl_->counters.messages_sent;
  return true;
}

bool WebRtcPeer::send_raw(Channel which, std::span<const uint8_t> bytes) {
  Impl& m = *impl_;
  if (bytes.size() > kMaxChannelMessage) return false;
  if (m.options.relayed) which = Channel::Reliable;
  if (!m.options.guard) return m.send_on_channel(which == Channel::Fast, bytes);
  return m.send_on_channel(which == Channel::Fast, bytes, true);
}

bool WebRtcPeer::send_handshake(std::span<const uint8_t> frame) { return impl_->send_on_channel(false, frame); }

bool WebRtcPeer::Impl::send_on_channel(bool on_fast, std::span<const uint8_t> bytes, bool seal) {
  std::lock_guard lock(mutex);
  GstWebRTCDataChannel* channel = on_fast ? fast : reliable;
  if (!channel) return false;
  // Sending on a channel that is not open yet crashes webrtcbin 1.22: ask first.
  GstWebRTCDataChannelState state = GST_WEBRTC_DATA_CHANNEL_STATE_CLOSED;
  g_object_get(channel, "ready-state", &state, nullptr);
  if (state != GST_WEBRTC_DATA_CHANNEL_STATE_OPEN) return false;
  // Sealed here, under the lock, after the channel said it is open: sealing numbers the record, and
  // the reliable channel opens records in strict order, so one sealed and not sent, or sent after a
  // later one (senders on several threads), would break it for good.
  std::optional<std::vector<uint8_t>> sealed;
  if (seal) {
    sealed = options.guard->seal(on_fast ? GuardedChannel::Fast : GuardedChannel::Reliable, bytes);
    if (!sealed || sealed->size() > kMaxChannelMessage) return false;
    bytes = *sealed;
  }
  GBytes* data = g_bytes_new(bytes.data(), bytes.size());
  gst_webrtc_data_channel_send_data(channel, data);
  g_bytes_unref(data);
  counters.channel_bytes_sent += bytes.size();
  return true;
}

void WebRtcPeer::request_keyframe() {
  for (GstElement* encoder : {impl_->color_enc, impl_->depth_enc})
    gst_element_send_event(encoder, gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
}

bool WebRtcPeer::set_simulated_loss(double fraction) {
  if (!(fraction >= 0 && fraction <= 1)) throw std::invalid_argument("a loss is a fraction between 0 and 1");
  std::lock_guard lock(impl_->mutex);
  if (!impl_->netsim) return false;
  g_object_set(impl_->netsim, "drop-probability", gfloat(fraction), nullptr);
  return true;
}

bool WebRtcPeer::send_voice(std::span<const uint8_t> packet, uint64_t capture_us, uint32_t frame_samples) {
  return impl_->voice.send(packet, capture_us, frame_samples);
}

std::vector<ReceivedVoice> WebRtcPeer::take_voice() { return impl_->voice.take(); }

std::optional<ReceivedPortrait> WebRtcPeer::take_portrait() {
  PendingFrame part;
  {
    std::lock_guard lock(impl_->mutex);
    if (impl_->paired.empty()) return std::nullopt;
    part = std::move(impl_->paired.front());
    impl_->paired.pop_front();
  }
  return Impl::assemble(std::move(part));
}

std::vector<net::Message> WebRtcPeer::take_messages() {
  std::lock_guard lock(impl_->mutex);
  return std::exchange(impl_->messages, {});
}

WebRtcCounters WebRtcPeer::counters() const {
  const Impl& m = *impl_;
  const RepairCounters repair = m.retransmission.read();
  std::lock_guard lock(m.mutex);
  WebRtcCounters out = m.counters;
  out.width_sent = m.sent_width;
  out.height_sent = m.sent_height;
  out.repair = repair;
  out.voice = m.voice.counters();
  out.color_encode_ms = m.color_encode.median_ms();
  out.depth_encode_ms = m.depth_encode.median_ms();
  out.keyframes_asked_of_us = m.asked_of_us.count();
  for (const auto& chain : m.chains) {
    (chain->color ? out.color_decode_ms : out.depth_decode_ms) = chain->decode.median_ms();
    out.keyframes_asked += chain->asked.count();
    const TrackLosses::Summary loss = chain->losses.summary();
    WebRtcCounters::TrackLoss& track = chain->color ? out.color_loss : out.depth_loss;
    track.packets_lost = loss.packets_lost;
    track.episodes = loss.episodes;
    track.recovered = loss.recovered;
    track.keyframes_asked = chain->asked.count();
    track.recovery_ms_median = loss.recovery_ms_median;
    track.recovery_ms_max = loss.recovery_ms_max;
  }
  if (m.bitrate) {
    const BitrateFollowerState rate = m.bitrate->state();
    out.color_kbps_now = rate.color_kbps;
    out.depth_kbps_now = rate.depth_kbps;
    out.reported_fraction_lost = rate.fraction_lost;
    out.round_trip_ms = rate.round_trip_ms;
    out.bitrate_decisions = rate.decisions;
    out.bitrate_lowered = rate.lowered;
    out.bitrate_raised = rate.raised;
    out.size_steps_down = rate.size_steps_down;
    out.size_steps_up = rate.size_steps_up;
  }
  return out;
}

std::string WebRtcPeer::last_error() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->last_error;
}

}  // namespace rt::media
