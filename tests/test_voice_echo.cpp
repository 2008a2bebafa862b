// The voice: the echo canceller (webrtcdsp) on the simulated room's echo path, its enhancement
// after 2 s; and a spoken sentence through Opus and the jitter buffer arriving whole.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "audio/simulated_room.h"
#include "audio/wav_file.h"
#include "media/echo_canceller.h"
#include "media/opus_voice.h"
#include "media/voice_jitter_buffer.h"
#include "media/voice_quality.h"
#include "support/output_dir.h"

using namespace rt;

namespace {

// A sentence spoken by espeak-ng, made at test time (never committed), at 48 kHz.
std::vector<float> voice_echo_sentence(const std::string& name, const std::string& text) {
  const auto dir = test::output_dir("test_voice_echo");
  std::filesystem::create_directories(dir);
  const auto path = (dir / (name + ".wav")).string();
  const std::string command = "espeak-ng -v en-us -s 150 -w '" + path + "' '" + text + "'";
  INFO("needs espeak-ng (scripts/packages.txt): " << command);
  REQUIRE(std::system(command.c_str()) == 0);
  return audio::read_wav_file(path, 30.0);
}

}  // namespace

TEST_CASE("voice: the echo canceller takes the room's echo down by at least 20 dB after 2 s", "[voice][echo]") {
  auto far = voice_echo_sentence("far", "We will clap our hands through the screen when you are ready. Can you hear me clearly now?");
  // Six seconds of the far user's speech, as played at this site.
  const size_t total = 6 * audio::kSampleRate;
  std::vector<float> played(total);
  for (size_t i = 0; i < total; ++i) played[i] = far[i % far.size()];
  audio::SimulatedRoom room({}, audio::EchoPathOptions{});  // the near user silent: echo alone
  auto speaker = room.loudspeaker();
  auto mic = room.microphone();
  media::EchoCanceller canceller;
  std::vector<float> heard, cleaned, block(audio::kBlockSamples);
  heard.reserve(total);
  cleaned.reserve(total);
  for (size_t i = 0; i + audio::kBlockSamples <= total; i += audio::kBlockSamples) {
    const std::span<const float> out(played.data() + i, audio::kBlockSamples);
    speaker->write(out);
    canceller.played(out);
    REQUIRE(mic->read(block));
    const auto clean = canceller.captured(block);
    heard.insert(heard.end(), block.begin(), block.end());
    cleaned.insert(cleaned.end(), clean.begin(), clean.end());
  }
  const double erle = media::echo_return_loss_enhancement_db(heard, cleaned, 2 * audio::kSampleRate, heard.size());
  const double first = media::echo_return_loss_enhancement_db(heard, cleaned, 0, audio::kSampleRate / 2);
  WARN("ERLE after 2 s: " << erle << " dB (first 0.5 s: " << first << " dB)");
  CHECK(erle >= 20.0);
}

TEST_CASE("voice: a sentence through Opus and a jittery network arrives whole", "[voice]") {
  const auto said = voice_echo_sentence("near", "Hello from site A. Put your hand on the glass and we will clap together.");
  media::VoiceEncoder encoder;
  media::VoiceDecoder decoder;
  // Frames leave every 20 ms and arrive late by up to 50 ms, out of order.
  std::mt19937 random(49);
  std::vector<std::pair<double, net::VoiceMessage>> in_flight;
  size_t bytes = 0;
  const size_t frames = said.size() / media::kVoiceFrameSamples + 10;
  for (size_t f = 0; f < frames; ++f) {
    std::vector<float> frame(media::kVoiceFrameSamples, 0.0f);
    for (size_t i = 0; i < frame.size(); ++i)
      if (f * frame.size() + i < said.size()) frame[i] = said[f * frame.size() + i];
    net::VoiceMessage m{f * 20000, uint32_t(f), uint16_t(media::kVoiceFrameSamples), encoder.encode(frame)};
    bytes += m.packet.size();
    in_flight.emplace_back(f * 20.0 + std::uniform_real_distribution<double>(0.0, 50.0)(random), std::move(m));
  }
  const double kbps = double(bytes) * 8.0 / (double(frames) * 0.020) / 1000.0;
  CHECK(kbps >= 24.0);
  CHECK(kbps <= 32.0);
  std::sort(in_flight.begin(), in_flight.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  media::VoiceJitterBuffer jitter;
  std::vector<float> heard;
  size_t next = 0;
  for (size_t tick = 0; tick < frames + 20 && jitter.counters().played < frames; ++tick) {
    while (next < in_flight.size() && in_flight[next].first <= tick * 20.0) jitter.push(std::move(in_flight[next++].second));
    const auto playout = jitter.pop();
    std::vector<float> out(media::kVoiceFrameSamples, 0.0f);
    if (playout.slot == media::VoiceJitterBuffer::Slot::Frame) out = decoder.decode(playout.frame.packet);
    if (playout.slot == media::VoiceJitterBuffer::Slot::Lost) out = decoder.conceal();
    heard.insert(heard.end(), out.begin(), out.end());
  }
  CHECK(jitter.counters().lost == 0);
  CHECK(jitter.counters().played == frames);
  const auto match = media::envelope_match(said, heard, 0.5);
  WARN("envelope correlation " << match.correlation << " at " << match.lag_ms << " ms");
  CHECK(match.correlation >= 0.9);
}
