#include "audio/audio_spec.h"

#include <stdexcept>

#include "audio/pulse_device.h"
#include "audio/wav_file.h"

namespace rt::audio {

AudioSpec parse_audio_spec(const std::string& text, const char* option) {
  AudioSpec spec;
  if (text.empty() || text == "none") return spec;
  if (text == "simulated") {
    spec.kind = AudioSpec::Kind::Simulated;
    return spec;
  }
  if (text == "pulse" || text.rfind("pulse:", 0) == 0) {
    spec.kind = AudioSpec::Kind::Live;
    spec.target = text.size() > 6 ? text.substr(6) : std::string();
    return spec;
  }
  if (text.size() > 4 && text.compare(text.size() - 4, 4, ".wav") == 0) {
    spec.kind = AudioSpec::Kind::WavFile;
    spec.target = text;
    return spec;
  }
  throw std::invalid_argument(std::string(option) + " '" + text +
                              "': give none, simulated, pulse (the sound server's default), pulse:DEVICE or a .wav file");
}

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

OpenedOutput open_audio_output(const AudioSpec& spec, std::function<uint64_t()> clock) {
  OpenedOutput opened;
  switch (spec.kind) {
    case AudioSpec::Kind::None: opened.description = "no sound out (none asked for)"; break;
    case AudioSpec::Kind::Simulated: throw std::logic_error("the simulated room is built by the site, with its scene");
    case AudioSpec::Kind::WavFile:
      opened.device = std::make_unique<WavFileOutput>(spec.target, std::move(clock));
      opened.description = opened.device->description();
      break;
    case AudioSpec::Kind::Live: {
      PulseOutputResult live = open_pulse_output(spec.target);
      opened.device = std::move(live.output);
      opened.description = live.message;
      break;
    }
  }
  return opened;
}

}  // namespace rt::audio
