#pragma once
// The site's sound: the microphone's voice, with the room's echo cancelled, sent as Opus frames
// over the session; the other site's voice taken from the session through the jitter buffer to
// the loudspeaker. One thread, 10 ms a tick on the wall clock (sound does not slow down with the
// scene's time scale: a voice at the wrong speed is no voice).
//
// The simulated room (the default) has the simulated user say a sentence of its own, made with
// espeak-ng when the site starts, and echoes the loudspeaker into the microphone when the scene
// asks for a room_echo; the site then writes what its loudspeaker played to audio.wav. A device
// that cannot be opened leaves the site without that half of the sound and says so.
//
// The loudspeakers are a stereo pair: the voice comes from both, a touch's sound (the clap) from
// where the palms meet, starting at the sample that plays at the moment it is asked for.
#include <atomic>
#include <limits>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "audio/audio_device.h"
#include "media/marker_claps.h"
#include "media/touch_sound.h"
#include "media/voice_hold.h"
#include "geometry/site_frames.h"
#include "net/transport.h"
#include "sim/effects.h"
#include "site/site_sound_options.h"

namespace rt::audio {
class SimulatedRoom;
class WavFileOutput;
}  // namespace rt::audio
namespace rt::media {
class EchoCanceller;
class VoiceEncoder;
class VoiceDecoder;
class VoiceJitterBuffer;
}  // namespace rt::media

namespace rt::site {

// What the simulated user at `site` says, and when (seconds after the sites connect): the two
// take turns, so that each site's echo canceller meets the far voice alone.
std::string simulated_sentence(Site site);
double simulated_sentence_start_s(Site site);

// Speaks `text` with espeak-ng into a WAV under `folder` and reads it back at 48 kHz. Throws
// std::runtime_error saying how to install espeak-ng when it is missing.
std::vector<float> speak_with_espeak(const std::string& text, const std::filesystem::path& folder);

class SiteSound {
 public:
  // Throws std::invalid_argument for an --audio-in or --audio-out that names nothing it knows.
  SiteSound(const SoundOptions& options, Site site, const sim::Effects& effects, const std::filesystem::path& out,
            net::Transport& transport, std::function<void(const std::string&)> log);
  ~SiteSound();

  // At connect. `marker_claps_us`: when the simulated user claps a sound-against-picture marker
  // (this site's monotonic clock); a simulated microphone hears them, any other ignores them.
  void start(const std::vector<uint64_t>& marker_claps_us = {});
  void stop();   // joins the thread, completes the files

  // A voice frame from the other site (the transport's thread): held until the sound thread takes
  // it, at most a few seconds' worth (the oldest go first).
  void receive(net::VoiceMessage frame);

  // Plays a touch's sound from `onset_us` (this site's monotonic clock) on, at `placement`; an
  // onset already past starts with the next block. Any thread. Returns an id for
  // cancel_touch_sound (0: no loudspeaker, nothing will play).
  uint64_t play_touch_sound(media::TouchSound sound, uint64_t onset_us, const media::StereoPlacement& placement);
  // Withdraws it if it has not begun (a predicted contact that did not come); any thread.
  void cancel_touch_sound(uint64_t id);

  // Holds the far voice to the far portrait: its capture-to-play latency follows `latency_ms`, the
  // portrait's capture-to-screen latency, plus kVoiceAfterPortraitMs (NaN: play the voice as it
  // comes). Any thread.
  void hold_voice_to(double latency_ms) { hold_to_ms_ = latency_ms + kVoiceAfterPortraitMs; }
  // ITU-R BT.1359 lets the sound come 45 ms early but 125 ms late, and every picture slower than
  // the median (a loaded moment, a frame skipped, one held on screen until the next) makes the
  // sound early: aimed at the median itself, a slow picture puts it past the early edge. Aimed at
  // the window's middle, a picture may come 85 ms later or earlier than usual and stay inside.
  static constexpr double kVoiceAfterPortraitMs = (125.0 - 45.0) / 2.0;
  // The far voice's median capture-to-play latency so far (NaN: none played yet); after stop().
  double voice_latency_ms() const { return voice_hold_.median_latency_ms(); }

  std::string description() const { return description_; }
  // audio.wav, what the simulated loudspeakers played (empty where they are not simulated), and
  // when its first sample played (0 before it has).
  std::filesystem::path heard_path() const { return heard_path_; }
  uint64_t heard_start_us() const;
  nlohmann::json metrics() const;

 private:
  void loop();
  // `play_us`: when the block's first sample plays (is handed to the loudspeaker).
  void tick(uint64_t block_index, uint64_t play_us);
  void take_touch_sound_requests(uint64_t block_index, uint64_t play_us);

  SoundOptions options_;
  net::Transport& transport_;
  std::mutex received_mutex_;
  std::deque<net::VoiceMessage> received_;
  uint64_t received_dropped_ = 0;

  struct TouchSoundRequest {
    uint64_t id = 0;
    media::TouchSound sound = media::TouchSound::Clap;
    uint64_t onset_us = 0;
    media::StereoPlacement placement;
  };
  // A touch's sound asked for and not yet scheduled, and the ones to withdraw (under received_mutex_).
  std::vector<TouchSoundRequest> touch_requests_;
  std::vector<uint64_t> touch_cancels_;
  uint64_t next_touch_id_ = 1;
  // What became of each (the sound thread's, read by metrics() after stop()): the first few.
  struct TouchSoundPlayed {
    TouchSoundRequest request;
    uint64_t mixer_id = 0;
    uint64_t onset_sample = 0;  // in the loudspeakers' stream, from its first sample
    uint64_t played_us = 0;     // when that sample plays
    bool cancelled = false;
  };
  std::vector<TouchSoundPlayed> touch_sounds_;
  media::TouchSoundMixer touch_mixer_;
  std::function<void(const std::string&)> log_;
  std::string description_;
  std::unique_ptr<audio::SimulatedRoom> room_;
  std::unique_ptr<audio::AudioInput> in_;
  std::unique_ptr<audio::AudioOutput> out_;
  std::unique_ptr<audio::WavFileOutput> heard_file_;  // audio.wav: what the loudspeaker played
  std::filesystem::path heard_path_;
  std::unique_ptr<media::EchoCanceller> canceller_;
  std::unique_ptr<media::MarkerClaps> marker_claps_;
  std::vector<uint64_t> marker_claps_us_;
  std::unique_ptr<media::VoiceEncoder> encoder_;
  std::unique_ptr<media::VoiceDecoder> decoder_;
  std::unique_ptr<media::VoiceJitterBuffer> jitter_;
  size_t speech_delay_samples_ = 0;

  std::thread thread_;
  std::atomic<bool> stopping_{false};
  bool started_ = false;
  uint64_t start_us_ = 0, ticks_ = 0, late_ticks_ = 0;

  // The loop's alone until stop() has joined it.
  std::vector<float> capture_frame_;   // 20 ms being filled for the encoder
  media::VoiceHold voice_hold_;        // the decoded far voice, held to the portrait
  std::atomic<double> hold_to_ms_{std::numeric_limits<double>::quiet_NaN()};
  std::vector<float> speakers_;  // the block to the stereo pair, interleaved
  uint64_t block_play_us_ = 0;   // when the block being made plays
  uint32_t sequence_ = 0;
  uint64_t voice_bytes_out_ = 0, voice_frames_out_ = 0, voice_frames_in_ = 0;
  // The echo canceller's figure, summed as the blocks go: microphone and cleaned power over the
  // blocks after the first two seconds that held echo alone.
  double erle_in_ = 0.0, erle_out_ = 0.0;
  uint64_t erle_blocks_ = 0;
  double encode_ms_ = 0.0, loop_ms_ = 0.0, cpu_ms_ = 0.0;
};

}  // namespace rt::site
