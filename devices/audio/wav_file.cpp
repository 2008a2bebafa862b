#include "audio/wav_file.h"

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "audio/gst_audio.h"
#include "time/monotonic_clock.h"

namespace rt::audio {
namespace {

constexpr auto kWavStartTimeout = std::chrono::seconds(10);
std::string site_caps(int channels) {
  if (channels != 1 && channels != 2) throw std::invalid_argument("1 or 2 channels, not " + std::to_string(channels));
  return "audio/x-raw,format=F32LE,rate=48000,channels=" + std::to_string(channels) + ",layout=interleaved";
}

}  // namespace

WavFileInput::WavFileInput(const std::string& path, int channels) : path_(path) {
  const std::string caps = site_caps(channels);
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error("audio input " + path + ": no such file (give a WAV file, 'simulated' or 'pulse[:DEVICE]')");
  if (auto missing = missing_audio_elements({"filesrc", "wavparse", "audioconvert", "audioresample", "appsink"});
      !missing.empty())
    throw std::runtime_error("audio input " + path + ": " + missing);
  pipeline_ = parse_pipeline(std::string("filesrc name=file ! wavparse ! audioconvert ! audioresample ! ") + caps +
                             " ! appsink name=sink sync=false max-buffers=16");
  GstElement* file = gst_bin_get_by_name(GST_BIN(pipeline_), "file");
  g_object_set(file, "location", path.c_str(), nullptr);
  gst_object_unref(file);
  sink_ = gst_bin_get_by_name(GST_BIN(pipeline_), "sink");
  if (const std::string error = start_pipeline(pipeline_, kWavStartTimeout); !error.empty()) {
    gst_element_set_state(pipeline_, GST_STATE_NULL);
    gst_object_unref(sink_);
    gst_object_unref(pipeline_);
    throw std::runtime_error("audio input " + path + " is not a readable WAV file: " + error);
  }
}

WavFileInput::~WavFileInput() {
  gst_element_set_state(pipeline_, GST_STATE_NULL);
  gst_object_unref(sink_);
  gst_object_unref(pipeline_);
}

bool WavFileInput::pull_more() {
  if (ended_) return false;
  GstSample* sample = gst_app_sink_pull_sample(GST_APP_SINK(sink_));
  if (!sample) {
    ended_ = true;
    return false;
  }
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  GstMapInfo map;
  if (buffer && gst_buffer_map(buffer, &map, GST_MAP_READ)) {
    pending_.erase(pending_.begin(), pending_.begin() + ptrdiff_t(pending_offset_));
    pending_offset_ = 0;
    const size_t count = map.size / sizeof(float);
    pending_.reserve(pending_.size() + count);
    const size_t old = pending_.size();
    pending_.resize(old + count);
    std::memcpy(pending_.data() + old, map.data, count * sizeof(float));
    gst_buffer_unmap(buffer, &map);
  }
  gst_sample_unref(sample);
  return true;
}

size_t WavFileInput::read_samples(std::span<float> block) {
  size_t filled = 0;
  while (filled < block.size()) {
    if (pending_offset_ == pending_.size() && !pull_more()) break;
    const size_t n = std::min(block.size() - filled, pending_.size() - pending_offset_);
    std::copy_n(pending_.begin() + ptrdiff_t(pending_offset_), n, block.begin() + ptrdiff_t(filled));
    pending_offset_ += n;
    filled += n;
  }
  return filled;
}

bool WavFileInput::read(std::span<float> block) {
  const size_t filled = read_samples(block);
  std::fill(block.begin() + ptrdiff_t(filled), block.end(), 0.0f);
  return filled == block.size();
}

WavFileOutput::WavFileOutput(const std::string& path, std::function<uint64_t()> clock, int channels)
    : path_(path), clock_(clock ? std::move(clock) : std::function<uint64_t()>(monotonic_now_us)), channels_(channels) {
  const std::string caps = site_caps(channels);
  if (auto missing = missing_audio_elements({"appsrc", "audioconvert", "wavenc", "filesink"}); !missing.empty())
    throw std::runtime_error("audio output " + path + ": " + missing);
  pipeline_ = parse_pipeline(std::string("appsrc name=source format=time block=true max-bytes=1000000 caps=") + caps +
                             " ! audioconvert ! audio/x-raw,format=S16LE ! wavenc ! filesink name=file");
  GstElement* file = gst_bin_get_by_name(GST_BIN(pipeline_), "file");
  g_object_set(file, "location", path.c_str(), nullptr);
  gst_object_unref(file);
  source_ = gst_bin_get_by_name(GST_BIN(pipeline_), "source");
  if (const std::string error = start_pipeline(pipeline_, std::chrono::milliseconds(0)); !error.empty()) {
    gst_element_set_state(pipeline_, GST_STATE_NULL);
    gst_object_unref(source_);
    gst_object_unref(pipeline_);
    throw std::runtime_error("audio output " + path + " cannot be written: " + error);
  }
}

WavFileOutput::~WavFileOutput() {
  // A file left unfinished here has no caller to tell; finish() says why to those who call it.
  try {
    finish();
  } catch (const std::exception&) {
  }
  gst_object_unref(source_);
  gst_object_unref(pipeline_);
}

void WavFileOutput::write(std::span<const float> block) {
  if (finished_ || block.empty()) return;
  if (block.size() % size_t(channels_) != 0)
    throw std::invalid_argument("audio output " + path_ + ": a block of " + std::to_string(block.size()) +
                                " samples is not whole frames of " + std::to_string(channels_) + " channels");
  if (samples_ == 0) start_us_ = clock_();
  const size_t frames = block.size() / size_t(channels_);
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, block.size_bytes(), nullptr);
  gst_buffer_fill(buffer, 0, block.data(), block.size_bytes());
  GST_BUFFER_PTS(buffer) = gst_util_uint64_scale(samples_, GST_SECOND, kSampleRate);
  GST_BUFFER_DURATION(buffer) = gst_util_uint64_scale(frames, GST_SECOND, kSampleRate);
  samples_ += frames;
  if (gst_app_src_push_buffer(GST_APP_SRC(source_), buffer) != GST_FLOW_OK) {
    const std::string error = pending_bus_error(pipeline_);
    finished_ = true;
    gst_element_set_state(pipeline_, GST_STATE_NULL);
    throw std::runtime_error("audio output " + path_ + ": writing failed" + (error.empty() ? "" : ": " + error));
  }
}

void WavFileOutput::finish() {
  if (finished_) return;
  finished_ = true;
  if (const std::string error = drain_and_stop(pipeline_, source_, kWavStartTimeout); !error.empty())
    throw std::runtime_error("audio output " + path_ + " was not completed: " + error);
}

std::vector<float> read_wav_file(const std::string& path, double max_seconds, int channels) {
  WavFileInput input(path, channels);
  const size_t limit = size_t(max_seconds * kSampleRate) * size_t(channels);
  std::vector<float> samples;
  std::vector<float> block(kBlockSamples);
  while (true) {
    const size_t n = input.read_samples(block);
    const bool full = n == block.size();
    if (samples.size() + n > limit)
      throw std::runtime_error(path + " is longer than " + std::to_string(int(max_seconds)) + " s");
    samples.reserve(samples.size() + n);
    samples.insert(samples.end(), block.begin(), block.begin() + ptrdiff_t(n));
    if (!full) break;
  }
  return samples;
}

void write_wav_file(const std::string& path, std::span<const float> samples) {
  WavFileOutput output(path);
  for (size_t i = 0; i < samples.size(); i += kBlockSamples)
    output.write(samples.subspan(i, std::min(kBlockSamples, samples.size() - i)));
  output.finish();
}

}  // namespace rt::audio
