#include "media/echo_canceller.h"

#include <gst/app/gstappsink.h>
#include <gst/gst.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "audio/gst_audio.h"

namespace rt::media {
namespace {

const char* const kFloatCaps = "audio/x-raw,format=F32LE,rate=48000,channels=1,layout=interleaved";
// webrtcdsp takes 16-bit interleaved or float planar; 16-bit is what it was tuned with.
const char* const kDspCaps = "audio/x-raw,format=S16LE,rate=48000,channels=1";

void require_dsp_element(const char* name) {
  GstElementFactory* factory = gst_element_factory_find(name);
  if (!factory)
    throw std::runtime_error(std::string("echo cancellation needs the GStreamer element ") + name +
                             ", which is missing: apt-get install gstreamer1.0-plugins-bad");
  gst_object_unref(factory);
}


GstElement* child(GstElement* pipeline, const char* name) { return gst_bin_get_by_name(GST_BIN(pipeline), name); }

// A source pad of our own on the pipeline's first element. A buffer pushed on it runs the whole
// chain in the calling thread, up to the appsink: no streaming thread to wake and wait for each
// 10 ms, and the canceller's CPU is spent in, and counted for, the sound thread.
GstPad* feed_pad(GstElement* pipeline, const char* first, const std::string& stream) {
  GstElement* head = child(pipeline, first);
  GstPad* sink = head ? gst_element_get_static_pad(head, "sink") : nullptr;
  GstPad* pad = GST_PAD(gst_object_ref_sink(gst_pad_new("feed", GST_PAD_SRC)));
  const bool linked = sink && gst_pad_set_active(pad, TRUE) && gst_pad_link(pad, sink) == GST_PAD_LINK_OK;
  if (sink) gst_object_unref(sink);
  if (head) gst_object_unref(head);
  if (!linked) {
    gst_object_unref(pad);
    throw std::runtime_error("echo canceller: cannot feed the pipeline's " + std::string(first));
  }
  // The sticky events a stream begins with, in the order the elements expect them.
  gst_pad_push_event(pad, gst_event_new_stream_start(stream.c_str()));
  GstCaps* caps = gst_caps_from_string(kFloatCaps);
  gst_pad_push_event(pad, gst_event_new_caps(caps));
  gst_caps_unref(caps);
  GstSegment segment;
  gst_segment_init(&segment, GST_FORMAT_TIME);
  gst_pad_push_event(pad, gst_event_new_segment(&segment));
  return pad;
}

void push_block(GstPad* feed, std::span<const float> block, uint64_t& samples) {
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, block.size_bytes(), nullptr);
  gst_buffer_fill(buffer, 0, block.data(), block.size_bytes());
  GST_BUFFER_PTS(buffer) = gst_util_uint64_scale(samples, GST_SECOND, 48000);
  GST_BUFFER_DURATION(buffer) = gst_util_uint64_scale(block.size(), GST_SECOND, 48000);
  samples += block.size();
  if (const GstFlowReturn flow = gst_pad_push(feed, buffer); flow != GST_FLOW_OK)
    throw std::runtime_error(std::string("echo canceller: the pipeline stopped taking audio (") +
                             gst_flow_get_name(flow) + ")");
}

// One block out of `sink`: it is there already, since the push ran the chain to the appsink;
// webrtcdsp hands back each 10 ms it was given.
std::vector<float> pull_block(GstElement* sink, GstElement* pipeline) {
  GstSample* sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 0);
  if (!sample) {
    std::string why = "no audio came out of the block pushed in";
    GstBus* bus = gst_element_get_bus(pipeline);
    if (GstMessage* message = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
      GError* error = nullptr;
      gst_message_parse_error(message, &error, nullptr);
      if (error) why = error->message, g_error_free(error);
      gst_message_unref(message);
    }
    gst_object_unref(bus);
    throw std::runtime_error("echo canceller: " + why);
  }
  std::vector<float> out;
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  GstMapInfo map;
  if (buffer && gst_buffer_map(buffer, &map, GST_MAP_READ)) {
    out.resize(map.size / sizeof(float));
    std::memcpy(out.data(), map.data, out.size() * sizeof(float));
    gst_buffer_unmap(buffer, &map);
  }
  gst_sample_unref(sample);
  return out;
}

void start(GstElement* pipeline) {
  if (gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("echo canceller: the pipeline would not start");
}

void release(GstElement*& pipeline, GstPad*& feed, std::initializer_list<GstElement**> elements) {
  if (feed) gst_pad_set_active(feed, FALSE), gst_object_unref(feed), feed = nullptr;
  if (pipeline) gst_element_set_state(pipeline, GST_STATE_NULL);
  for (GstElement** e : elements)
    if (*e) gst_object_unref(*e), *e = nullptr;
  if (pipeline) gst_object_unref(pipeline), pipeline = nullptr;
}

}  // namespace

EchoCanceller::EchoCanceller(const EchoCancellerOptions& options) {
  static std::once_flag once;
  std::call_once(once, [] { gst_init(nullptr, nullptr); });
  require_dsp_element("webrtcdsp");
  require_dsp_element("webrtcechoprobe");
  // The canceller finds its probe by name among all in the process: one name per canceller.
  static std::atomic<int> next_probe{0};
  const std::string probe = "rt_echo_probe_" + std::to_string(next_probe++);
  const std::string sinks = " sync=false async=false max-buffers=64";
  try {
    far_pipeline_ = audio::parse_pipeline(std::string("audioconvert name=head ! ") +
                           kDspCaps + " ! webrtcechoprobe name=" + probe + " ! appsink name=sink" + sinks);
    far_sink_ = child(far_pipeline_, "sink");
    near_pipeline_ = audio::parse_pipeline(std::string("audioconvert name=head ! ") +
                            kDspCaps + " ! webrtcdsp name=dsp probe=" + probe +
                            " echo-cancel=true delay-agnostic=true extended-filter=true"
                            " echo-suppression-level=high noise-suppression=" +
                            (options.noise_suppression ? "true" : "false") +
                            " gain-control=" + (options.gain_control ? "true" : "false") +
                            " high-pass-filter=true ! audioconvert ! " + kFloatCaps + " ! appsink name=sink" + sinks);
    near_sink_ = child(near_pipeline_, "sink");
    start(far_pipeline_);
    start(near_pipeline_);
    far_feed_ = feed_pad(far_pipeline_, "head", probe + "_played");
    near_feed_ = feed_pad(near_pipeline_, "head", probe + "_captured");
  } catch (...) {
    release(near_pipeline_, near_feed_, {&near_sink_});
    release(far_pipeline_, far_feed_, {&far_sink_});
    throw;
  }
}

EchoCanceller::~EchoCanceller() {
  release(near_pipeline_, near_feed_, {&near_sink_});
  release(far_pipeline_, far_feed_, {&far_sink_});
}

void EchoCanceller::played(std::span<const float> block) {
  if (block.size() != kBlockSamples)
    throw std::invalid_argument("echo canceller: a played block is 480 samples, not " + std::to_string(block.size()));
  push_block(far_feed_, block, far_samples_);
  // Read back (the probe has taken the block: the push ran through it), so that the appsink's
  // queue does not grow.
  pull_block(far_sink_, far_pipeline_);
}

std::vector<float> EchoCanceller::captured(std::span<const float> block) {
  if (block.size() != kBlockSamples)
    throw std::invalid_argument("echo canceller: a captured block is 480 samples, not " + std::to_string(block.size()));
  push_block(near_feed_, block, near_samples_);
  std::vector<float> out = pull_block(near_sink_, near_pipeline_);
  out.resize(kBlockSamples, 0.0f);
  return out;
}

double echo_return_loss_enhancement_db(std::span<const float> microphone, std::span<const float> cancelled, size_t from,
                                       size_t to) {
  to = std::min({to, microphone.size(), cancelled.size()});
  double in = 0.0, out = 0.0;
  for (size_t i = from; i < to; ++i) {
    in += double(microphone[i]) * microphone[i];
    out += double(cancelled[i]) * cancelled[i];
  }
  // A floor under the output: perfect silence reads as 100 dB, not infinity.
  return 10.0 * std::log10(std::max(in, 1e-20) / std::max(out, in * 1e-10 + 1e-20));
}

}  // namespace rt::media
