#include "audio/pulse_device.h"

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "audio/gst_audio.h"

namespace rt::audio {
namespace {

const char* const kLiveCaps = "audio/x-raw,format=F32LE,rate=48000,channels=1,layout=interleaved";
// A live microphone whose reader stalls drops its oldest audio rather than growing: a second.
constexpr int kMaxQueuedCaptureBuffers = 100;

std::string device_label(const std::string& device) {
  return device.empty() ? "the sound server's default" : "'" + device + "'";
}

// Connects the pipeline to the server (NULL -> READY opens the device) and says why it cannot.
std::string open_on_server(GstElement* pipeline, bool wait_until_playing) {
  if (gst_element_set_state(pipeline, GST_STATE_READY) == GST_STATE_CHANGE_FAILURE) {
    std::string error = pending_bus_error(pipeline);
    return error.empty() ? "the sound server refused the device" : error;
  }
  if (gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    std::string error = pending_bus_error(pipeline);
    return error.empty() ? "the device would not start" : error;
  }
  // Until the state change completes, an appsink answers a pull with nothing: wait for it.
  // (A sink waits for its first buffer instead: nothing to wait for there.)
  if (wait_until_playing &&
      gst_element_get_state(pipeline, nullptr, nullptr, 2 * GST_SECOND) == GST_STATE_CHANGE_FAILURE) {
    std::string error = pending_bus_error(pipeline);
    return error.empty() ? "the device failed while starting" : error;
  }
  return pending_bus_error(pipeline);
}

void discard(GstElement* pipeline, GstElement* end) {
  gst_element_set_state(pipeline, GST_STATE_NULL);
  if (end) gst_object_unref(end);
  gst_object_unref(pipeline);
}

class PulseInput final : public AudioInput {
 public:
  PulseInput(GstElement* pipeline, GstElement* sink, std::string label)
      : pipeline_(pipeline), sink_(sink), label_(std::move(label)) {}
  ~PulseInput() override { discard(pipeline_, sink_); }

  bool read(std::span<float> block) override {
    size_t filled = 0;
    while (filled < block.size() && !ended_) {
      if (offset_ == pending_.size()) {
        GstSample* sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink_), GST_SECOND);
        if (!sample) {
          ended_ = true;  // the server went away or the device stopped delivering
          break;
        }
        GstBuffer* buffer = gst_sample_get_buffer(sample);
        GstMapInfo map;
        pending_.clear();
        offset_ = 0;
        if (buffer && gst_buffer_map(buffer, &map, GST_MAP_READ)) {
          pending_.resize(map.size / sizeof(float));
          std::memcpy(pending_.data(), map.data, pending_.size() * sizeof(float));
          gst_buffer_unmap(buffer, &map);
        }
        gst_sample_unref(sample);
        continue;
      }
      const size_t n = std::min(block.size() - filled, pending_.size() - offset_);
      std::copy_n(pending_.begin() + ptrdiff_t(offset_), n, block.begin() + ptrdiff_t(filled));
      offset_ += n;
      filled += n;
    }
    std::fill(block.begin() + ptrdiff_t(filled), block.end(), 0.0f);
    return filled == block.size();
  }
  std::string description() const override { return "live input " + label_; }

 private:
  GstElement* pipeline_;
  GstElement* sink_;
  std::string label_;
  std::vector<float> pending_;
  size_t offset_ = 0;
  bool ended_ = false;
};

class PulseOutput final : public AudioOutput {
 public:
  PulseOutput(GstElement* pipeline, GstElement* source, std::string label, int channels)
      : pipeline_(pipeline), source_(source), label_(std::move(label)), channels_(channels) {}
  ~PulseOutput() override { discard(pipeline_, source_); }

  void write(std::span<const float> block) override {
    if (failed_ || block.empty()) return;
    const size_t frames = block.size() / size_t(channels_);
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, frames * size_t(channels_) * sizeof(float), nullptr);
    gst_buffer_fill(buffer, 0, block.data(), frames * size_t(channels_) * sizeof(float));
    GST_BUFFER_PTS(buffer) = gst_util_uint64_scale(samples_, GST_SECOND, kSampleRate);
    GST_BUFFER_DURATION(buffer) = gst_util_uint64_scale(frames, GST_SECOND, kSampleRate);
    samples_ += frames;
    // A device that vanished mid-call silences the site; the call goes on.
    if (gst_app_src_push_buffer(GST_APP_SRC(source_), buffer) != GST_FLOW_OK) failed_ = true;
  }
  std::string description() const override { return "live output " + label_; }
  int channels() const override { return channels_; }

 private:
  GstElement* pipeline_;
  GstElement* source_;
  std::string label_;
  int channels_ = 1;
  uint64_t samples_ = 0;  // frames
  bool failed_ = false;
};

}  // namespace

PulseInputResult open_pulse_input(const std::string& device) {
  PulseInputResult result;
  const std::string label = device_label(device);
  if (auto missing = missing_audio_elements({"pulsesrc", "audioconvert", "audioresample", "appsink"}); !missing.empty()) {
    result.message = "no sound in: " + missing;
    return result;
  }
  GstElement* pipeline = parse_pipeline(std::string("pulsesrc name=device ! audioconvert ! audioresample ! ") +
                                        kLiveCaps + " ! appsink name=sink sync=false drop=true max-buffers=" +
                                        std::to_string(kMaxQueuedCaptureBuffers));
  GstElement* source = gst_bin_get_by_name(GST_BIN(pipeline), "device");
  if (!device.empty()) g_object_set(source, "device", device.c_str(), nullptr);
  g_object_set(source, "client-name", "RemoteTouch", nullptr);
  gst_object_unref(source);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  if (const std::string error = open_on_server(pipeline, true); !error.empty()) {
    discard(pipeline, sink);
    result.message = "no sound in: cannot open " + label + " input (" + error +
                     "); is a PulseAudio or PipeWire server running? `pactl list short sources` names the inputs";
    return result;
  }
  result.input = std::make_unique<PulseInput>(pipeline, sink, label);
  result.message = result.input->description();
  return result;
}

PulseOutputResult open_pulse_output(const std::string& device, int channels) {
  PulseOutputResult result;
  if (channels != 1 && channels != 2) throw std::invalid_argument("a live output has 1 or 2 channels, not " + std::to_string(channels));
  const std::string label = device_label(device);
  if (auto missing = missing_audio_elements({"appsrc", "pulsesink", "audioconvert", "audioresample"}); !missing.empty()) {
    result.message = "no sound out: " + missing;
    return result;
  }
  // The site paces its blocks itself; the sink plays them as they come.
  GstElement* pipeline = parse_pipeline(std::string("appsrc name=source is-live=true format=time block=false caps=") +
                                        "audio/x-raw,format=F32LE,rate=48000,channels=" + std::to_string(channels) +
                                        ",layout=interleaved ! audioconvert ! audioresample ! pulsesink name=device sync=false");
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "device");
  if (!device.empty()) g_object_set(sink, "device", device.c_str(), nullptr);
  g_object_set(sink, "client-name", "RemoteTouch", nullptr);
  gst_object_unref(sink);
  GstElement* source = gst_bin_get_by_name(GST_BIN(pipeline), "source");
  if (const std::string error = open_on_server(pipeline, false); !error.empty()) {
    discard(pipeline, source);
    result.message = "no sound out: cannot open " + label + " output (" + error +
                     "); is a PulseAudio or PipeWire server running? `pactl list short sinks` names the outputs";
    return result;
  }
  result.output = std::make_unique<PulseOutput>(pipeline, source, label, channels);
  result.message = result.output->description();
  return result;
}

}  // namespace rt::audio
