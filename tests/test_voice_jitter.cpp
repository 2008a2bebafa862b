// The voice's jitter buffer: it waits for its target before playing, plays in order, marks a
// lost frame for concealment, drops late and duplicate frames, and stays bounded.
#include <catch2/catch.hpp>

#include "media/opus_voice.h"
#include "media/voice_jitter_buffer.h"

using namespace rt;
using media::VoiceJitterBuffer;
using Slot = VoiceJitterBuffer::Slot;

namespace {

net::VoiceMessage voice_jitter_frame(uint32_t sequence) { return {sequence * 20000ull, sequence, 960, {uint8_t(sequence)}}; }

}  // namespace

TEST_CASE("voice jitter buffer: waits for its target, then plays in order and marks losses", "[voice]") {
  VoiceJitterBuffer jitter({.target_frames = 3, .capacity_frames = 10});
  CHECK(jitter.pop().slot == Slot::Silence);
  CHECK(jitter.push(voice_jitter_frame(101)));
  CHECK(jitter.push(voice_jitter_frame(100)));  // earlier than the first: playing starts here
  CHECK(jitter.pop().slot == Slot::Silence);     // two of three
  CHECK(jitter.push(voice_jitter_frame(103)));   // 102 is lost
  auto p = jitter.pop();
  REQUIRE(p.slot == Slot::Frame);
  CHECK(p.frame.sequence == 100);
  CHECK(jitter.pop().frame.sequence == 101);
  CHECK(jitter.pop().slot == Slot::Lost);
  CHECK_FALSE(jitter.push(voice_jitter_frame(102)));  // too late now
  CHECK(jitter.counters().late == 1);
  CHECK(jitter.pop().frame.sequence == 103);
  CHECK(jitter.push(voice_jitter_frame(104)));
  CHECK_FALSE(jitter.push(voice_jitter_frame(104)));
  CHECK(jitter.counters().duplicate == 1);
  CHECK(jitter.counters().lost == 1);
}

TEST_CASE("voice jitter buffer: a burst past its capacity keeps the newest, never grows", "[voice]") {
  VoiceJitterBuffer jitter({.target_frames = 2, .capacity_frames = 5});
  for (uint32_t s = 0; s < 40; ++s) jitter.push(voice_jitter_frame(s));
  CHECK(jitter.buffered() <= 5);
  CHECK(jitter.counters().overflow_dropped >= 35);
  const auto p = jitter.pop();
  REQUIRE(p.slot == Slot::Frame);
  CHECK(p.frame.sequence >= 35);
  CHECK_THROWS_WITH(VoiceJitterBuffer({.target_frames = 4, .capacity_frames = 2}), Catch::Contains("capacity 2 frames"));
}

TEST_CASE("voice codec: Opus frames of the wrong length are refused, damaged packets concealed", "[voice]") {
  media::VoiceEncoder encoder;
  std::vector<float> frame(960, 0.0f);
  const auto packet = encoder.encode(frame);
  CHECK(packet.size() >= 60);  // 28 kbit/s constant: 70 bytes a frame
  CHECK(packet.size() <= 80);
  CHECK_THROWS_WITH(encoder.encode(std::vector<float>(500)), Catch::Contains("960 samples, not 500"));
  CHECK_THROWS_WITH(media::VoiceEncoder({.bitrate_bps = 1000}), Catch::Contains("outside 6000..128000"));
  media::VoiceDecoder decoder;
  CHECK(decoder.decode(packet).size() == 960);
  const std::vector<uint8_t> garbage(3, 0xff);
  CHECK(decoder.decode(garbage).size() == 960);
  CHECK(decoder.undecodable() == 1);
}
