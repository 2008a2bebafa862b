#pragma once
// The live backend: a sound server's source and sink through GStreamer's pulsesrc and pulsesink
// (PulseAudio, or PipeWire's PulseAudio service). A device is chosen by its server name
// (`pactl list short sources`); none given means the server's default.
//
// No server or no such device is not a failure of the call: the result then holds no device
// and says why, and the site runs without sound.
#include <memory>
#include <string>

#include "audio/audio_device.h"

namespace rt::audio {

struct PulseInputResult {
  std::unique_ptr<AudioInput> input;  // null: no sound in, `message` says why
  std::string message;
};
struct PulseOutputResult {
  std::unique_ptr<AudioOutput> output;  // null: no sound out, `message` says why
  std::string message;
};

PulseInputResult open_pulse_input(const std::string& device);
// `channels`: 1 or 2 (interleaved, left first).
PulseOutputResult open_pulse_output(const std::string& device, int channels = 1);

}  // namespace rt::audio
