#pragma once
// What a site's sound takes from its command line (site_sound.h).
#include <string>

namespace rt::site {

struct SoundOptions {
  std::string audio_in = "simulated";   // none | simulated | pulse[:DEVICE] | FILE.wav
  std::string audio_out = "simulated";  // none | simulated | pulse[:DEVICE] | FILE.wav
  bool noise_suppression = false;
  bool gain_control = false;
  int voice_bitrate_bps = 28000;  // Opus, 24..32 kbit/s for speech
  bool lip_sync = true;           // the far voice held to the far portrait (false: played as it comes)
};

}  // namespace rt::site
