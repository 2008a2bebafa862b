#pragma once
// What `--audio-in` and `--audio-out` name: no sound, the simulated room, a WAV file, or a live
// device of the sound server (`pulse` for its default, `pulse:NAME` for one by name).
#include <functional>
#include <memory>
#include <string>

#include "audio/audio_device.h"

namespace rt::audio {

struct AudioSpec {
  enum class Kind { None, Simulated, WavFile, Live };
  Kind kind = Kind::None;
  std::string target;  // the file's path, or the live device's name (empty: the server's default)
};

// "none", "simulated", "pulse", "pulse:NAME" or a path ending in .wav. Throws
// std::invalid_argument saying what the forms are.
AudioSpec parse_audio_spec(const std::string& text, const char* option);

// A device opened from a spec other than Simulated (the site builds the room, which needs its
// scene). `device` is null for None and for a live device that cannot be opened: `description`
// then says why, and the site goes on without sound. A WAV file that cannot be read or written
// is the user's mistake and throws std::runtime_error.
struct OpenedInput {
  std::unique_ptr<AudioInput> device;
  std::string description;
};
struct OpenedOutput {
  std::unique_ptr<AudioOutput> device;
  std::string description;
};
OpenedInput open_audio_input(const AudioSpec& spec);
// `clock`: the site's monotonic clock, for a WAV file's start; `channels`: 1 or 2.
OpenedOutput open_audio_output(const AudioSpec& spec, std::function<uint64_t()> clock = {}, int channels = 1);

}  // namespace rt::audio
