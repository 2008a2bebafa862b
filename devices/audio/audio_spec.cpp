#include "audio/audio_spec.h"

#include <stdexcept>

#include "audio/pulse_device.h"
#include "audio/wav_file.h"

namespace rt::audio {

OpenedInput open_audio_input(const AudioSpec& spec) {
  OpenedInput opened;
  switch (spec.kind) {
    case AudioSpec::Kind::None: opened.description = "no sound in (none asked for)"; break;
    case AudioSpec::Kind::Simulated: throw std::logic_error("the simulated room is built by the site, with its scene");
    case AudioSpec::Kind::WavFile:
      opened.device = std::make_unique<WavFileInput>(spec.target);
      opened.description = opened.device->description();
      break;
    case AudioSpec::Kind::Live: {
      PulseInputResult live = open_pulse_input(spec.target);
      opened.device = std::move(live.input);
      opened.description = live.message;
      break;
    }
  }
  return opened;
}

OpenedOutput open_audio_output(const AudioSpec& spec, std::function<uint64_t()> clock, int channels) {
  OpenedOutput opened;
  switch (spec.kind) {
    case AudioSpec::Kind::None: opened.description = "no sound out (none asked for)"; break;
    case AudioSpec::Kind::Simulated: throw std::logic_error("the simulated room is built by the site, with its scene");
    case AudioSpec::Kind::WavFile:
      opened.device = std::make_unique<WavFileOutput>(spec.target, std::move(clock), channels);
      opened.description = opened.device->description();
      break;
    case AudioSpec::Kind::Live: {
      PulseOutputResult live = open_pulse_output(spec.target, channels);
      opened.device = std::move(live.output);
      opened.description = live.message;
      break;
    }
  }
  return opened;
}

}  // namespace rt::audio
