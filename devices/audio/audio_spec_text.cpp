// The spec's text alone, apart from the devices it opens: the config's fuzzer links just this.
#include <stdexcept>

#include "audio/audio_spec.h"

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

}  // namespace rt::audio
