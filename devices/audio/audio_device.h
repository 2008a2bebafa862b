#pragma once
// The site's microphone and loudspeaker. One interface each, three backends: a WAV file
// (wav_file.h: a recording played as the microphone, the loudspeaker written to a file), the
// simulated room (simulated_room.h: the simulated user's speech and the echo of the loudspeaker
// in the microphone) and a live sound server through GStreamer (pulse_device.h).
//
// Everything is 48 kHz float in [-1, 1], moved in blocks of any length; the site moves 10 ms
// blocks because the echo canceller works in those. The microphone is mono; an output has one or
// more channels, its blocks interleaved frames (left first): the site's loudspeakers are a stereo
// pair, so that a touch's sound comes from where the palms meet.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace rt::audio {

inline constexpr int kSampleRate = 48000;
inline constexpr size_t kBlockSamples = kSampleRate / 100;  // 10 ms
inline constexpr int kLoudspeakerChannels = 2;

inline uint64_t samples_to_us(uint64_t samples) { return samples * 1000000ull / kSampleRate; }

class AudioInput {
 public:
  virtual ~AudioInput() = default;
  // Fills all of `block` with the next samples. False once the input has nothing more to give
  // (a file's end, a device gone): the block is then silence from where the input stopped.
  virtual bool read(std::span<float> block) = 0;
  virtual std::string description() const = 0;
};

class AudioOutput {
 public:
  virtual ~AudioOutput() = default;
  // `block`: whole frames of channels() interleaved samples.
  virtual void write(std::span<const float> block) = 0;
  virtual int channels() const { return 1; }
  // Flushes what was written; a file is complete and readable only after this. Idempotent.
  virtual void finish() {}
  virtual std::string description() const = 0;
};

}  // namespace rt::audio
