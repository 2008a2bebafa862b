#pragma once
// The WAV-file backend: a recording played as the microphone, and the loudspeaker written to a
// file. GStreamer parses and writes the files (wavparse, wavenc) and converts any WAV (rate,
// channels, sample format) to the site's 48 kHz float: mono, or stereo where asked for.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "audio/audio_device.h"

typedef struct _GstElement GstElement;

namespace rt::audio {

class WavFileInput final : public AudioInput {
 public:
  // Throws std::runtime_error naming the file and what is wrong with it (missing, not a WAV).
  // `channels`: 1, or 2 (interleaved, left first; a mono file then gives both the same).
  explicit WavFileInput(const std::string& path, int channels = 1);
  ~WavFileInput() override;
  bool read(std::span<float> block) override;
  // As read(), without the silence past the end: how many samples it gave.
  size_t read_samples(std::span<float> block);
  std::string description() const override { return "WAV file " + path_; }

 private:
  bool pull_more();
  std::string path_;
  GstElement* pipeline_ = nullptr;
  GstElement* sink_ = nullptr;
  std::vector<float> pending_;
  size_t pending_offset_ = 0;
  bool ended_ = false;
};

class WavFileOutput final : public AudioOutput {
 public:
  // `clock`: microseconds of the site's monotonic clock, read at the first write: the file's
  // first sample was played then (start_us). Throws std::runtime_error when the file cannot be made.
  // `channels`: 1 (mono) or 2 (stereo, interleaved).
  explicit WavFileOutput(const std::string& path, std::function<uint64_t()> clock = {}, int channels = 1);
  ~WavFileOutput() override;
  void write(std::span<const float> block) override;
  void finish() override;
  std::string description() const override { return "WAV file " + path_; }
  int channels() const override { return channels_; }

  uint64_t start_us() const { return start_us_; }  // 0 until the first write
  uint64_t samples_written() const { return samples_; }  // frames

 private:
  std::string path_;
  std::function<uint64_t()> clock_;
  GstElement* pipeline_ = nullptr;
  GstElement* source_ = nullptr;
  uint64_t start_us_ = 0;
  int channels_ = 1;
  uint64_t samples_ = 0;  // frames
  bool finished_ = false;
};

// A whole file at once, for tests and the simulated user's sentence. Refuses files longer than
// `max_seconds` rather than allocating without bound.
std::vector<float> read_wav_file(const std::string& path, double max_seconds = 600.0, int channels = 1);
void write_wav_file(const std::string& path, std::span<const float> samples);

}  // namespace rt::audio
