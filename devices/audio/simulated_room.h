#pragma once
// The simulated backend: a room with the simulated user in it. Its microphone hears the user's
// speech and, when the scene asks for it, the echo of what its loudspeaker played: the direct
// path delayed and attenuated, and a few later reflections (a little reverb). Without an echo
// path the microphone hears the speech alone and the loudspeaker costs nothing but its record.
//
// The site plays a block, then reads one: an echo delay of at least one block means the
// microphone only ever hears what has already been played.
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "audio/audio_device.h"

namespace rt::audio {

struct EchoPathOptions {
  double delay_ms = 50.0;  // loudspeaker to microphone, direct path
  double gain_db = -6.0;   // of the direct path
  // Reflections after the direct path: this many, spread over `reverb_ms`, decaying to
  // `reverb_db` below the direct path at the last one.
  int reverb_taps = 6;
  double reverb_ms = 60.0;
  double reverb_db = -18.0;
};

// Empty when the options make a room of this kind (delay 10..500 ms, gain -60..0 dB, ...), else
// what is wrong.
std::string check_echo_path(const EchoPathOptions& options);

// The echo as an impulse response at 48 kHz: index = delay in samples.
struct EchoTap {
  size_t delay_samples = 0;
  float gain = 0.0f;
};
std::vector<EchoTap> echo_taps(const EchoPathOptions& options);

class SimulatedRoom {
 public:
  static constexpr size_t kRecordedSeconds = 120;

  // `speech`: what the user says, from the first sample read; silence after it. `echo`: none
  // means the microphone hears no loudspeaker. Throws std::invalid_argument for a bad echo path.
  // `record_seconds`: how much of the microphone's parts to keep for echo_heard() and
  // speech_heard() (a long-running site keeps none and reads last_block_powers() instead).
  SimulatedRoom(std::vector<float> speech, std::optional<EchoPathOptions> echo, size_t record_seconds = kRecordedSeconds);

  // Both refer to the room, which must outlive them.
  std::unique_ptr<AudioInput> microphone();
  // `channels`: 2 for the site's stereo pair, whose sum the microphone hears (they stand together).
  std::unique_ptr<AudioOutput> loudspeaker(int channels = 1);

  // What the microphone heard of the loudspeaker alone, and of the user alone (for the echo
  // canceller's figures): index = sample read. Kept for the first kRecordedSeconds only.
  std::vector<float> echo_heard() const;
  std::vector<float> speech_heard() const;
  std::vector<float> played() const;
  // The power (sum of squares) of the user's speech and of the echo in the last block read.
  struct BlockPowers {
    double speech = 0.0, echo = 0.0;
  };
  BlockPowers last_block_powers() const;
  bool has_echo() const { return !taps_.empty(); }

 private:
  friend class RoomMicrophone;
  friend class RoomLoudspeaker;
  void read_into(std::span<float> block);
  void play(std::span<const float> block);

  mutable std::mutex mutex_;
  std::vector<float> speech_;
  std::vector<EchoTap> taps_;
  std::deque<float> recent_;  // the last samples played, as far back as the echo reaches
  size_t reach_ = 0;
  uint64_t played_count_ = 0;
  std::vector<float> played_, echo_heard_, speech_heard_;  // the first kRecordedSeconds
  uint64_t read_ = 0;
  size_t recorded_limit_ = 0;
  BlockPowers last_powers_;
};

}  // namespace rt::audio
