// The audio devices: a WAV file round trip through GStreamer, clear errors for files that are not
// there or not WAV, a missing sound server as a site without sound, and the simulated room's echo
// only when asked for.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>

#include "audio/audio_spec.h"
#include "audio/pulse_device.h"
#include "audio/simulated_room.h"
#include "audio/wav_file.h"
#include "support/output_dir.h"

using namespace rt::audio;

namespace {

std::vector<float> audio_devices_tone(size_t samples, double hz, float amplitude) {
  std::vector<float> tone(samples);
  for (size_t i = 0; i < samples; ++i)
    tone[i] = amplitude * float(std::sin(2.0 * std::numbers::pi * hz * double(i) / kSampleRate));
  return tone;
}

}  // namespace

TEST_CASE("audio devices: a WAV file written and read back is the same sound", "[audio]") {
  const auto dir = rt::test::output_dir("test_audio_devices");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "tone.wav").string();
  const auto tone = audio_devices_tone(kSampleRate + 123, 440.0, 0.5f);
  uint64_t now_us = 5'000'000;
  {
    WavFileOutput out(path, [&] { return now_us; });
    for (size_t i = 0; i < tone.size(); i += 333)
      out.write(std::span(tone).subspan(i, std::min<size_t>(333, tone.size() - i)));
    out.finish();
    CHECK(out.start_us() == 5'000'000);
    CHECK(out.samples_written() == tone.size());
  }
  const auto back = read_wav_file(path);
  REQUIRE(back.size() == tone.size());
  double worst = 0.0;
  for (size_t i = 0; i < tone.size(); ++i) worst = std::max(worst, double(std::abs(back[i] - tone[i])));
  CHECK(worst < 2.0 / 32768.0);  // 16-bit PCM in the file

  // As a microphone: the file, then silence and false at its end.
  WavFileInput in(path);
  std::vector<float> block(kBlockSamples);
  size_t blocks = 0;
  while (in.read(block)) ++blocks;
  CHECK(blocks == tone.size() / kBlockSamples);
}

TEST_CASE("audio devices: a stereo WAV keeps its channels apart, and a block must be whole frames", "[audio]") {
  const auto dir = rt::test::output_dir("test_audio_devices");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "stereo.wav").string();
  const auto left = audio_devices_tone(4801, 440.0, 0.5f), right = audio_devices_tone(4801, 1000.0, 0.25f);
  std::vector<float> frames;
  frames.reserve(2 * left.size());
  for (size_t i = 0; i < left.size(); ++i) frames.insert(frames.end(), {left[i], right[i]});
  {
    WavFileOutput out(path, {}, 2);
    CHECK(out.channels() == 2);
    CHECK_THROWS_WITH(out.write(std::span(frames).first(3)), Catch::Contains("not whole frames of 2 channels"));
    out.write(frames);
    out.finish();
    CHECK(out.samples_written() == left.size());
  }
  const auto back = read_wav_file(path, 10.0, 2);
  REQUIRE(back.size() == frames.size());
  double worst = 0.0;
  for (size_t i = 0; i < frames.size(); ++i) worst = std::max(worst, double(std::abs(back[i] - frames[i])));
  CHECK(worst < 2.0 / 32768.0);
  // Read as mono, the two channels' mean.
  const auto mono = read_wav_file(path);
  REQUIRE(mono.size() == left.size());
  CHECK(mono[100] == Approx(0.5f * (left[100] + right[100])).margin(1e-3));
  CHECK_THROWS_WITH(WavFileOutput((dir / "three.wav").string(), {}, 3), Catch::Contains("1 or 2 channels, not 3"));
}

TEST_CASE("audio devices: a missing or broken WAV file is refused with the reason", "[audio]") {
  const auto dir = rt::test::output_dir("test_audio_devices");
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH(WavFileInput((dir / "nothing-here.wav").string()), Catch::Contains("no such file"));
  const auto text = (dir / "not-audio.wav").string();
  std::ofstream(text) << "this is not a WAV file, only text that pretends to be one by its name\n";
  CHECK_THROWS_WITH(WavFileInput(text), Catch::Contains("is not a readable WAV file"));
  CHECK_THROWS_WITH(WavFileOutput((dir / "no-such-folder" / "out.wav").string()), Catch::Contains("cannot be written"));
}

TEST_CASE("audio devices: the spec names none, simulated, live or a file", "[audio]") {
  CHECK(parse_audio_spec("", "--audio-in").kind == AudioSpec::Kind::None);
  CHECK(parse_audio_spec("simulated", "--audio-in").kind == AudioSpec::Kind::Simulated);
  CHECK(parse_audio_spec("pulse", "--audio-in").target.empty());
  const auto named = parse_audio_spec("pulse:alsa_output.pci.analog-stereo", "--audio-out");
  CHECK(named.kind == AudioSpec::Kind::Live);
  CHECK(named.target == "alsa_output.pci.analog-stereo");
  CHECK(parse_audio_spec("a/b.wav", "--audio-in").kind == AudioSpec::Kind::WavFile);
  CHECK_THROWS_WITH(parse_audio_spec("speakers", "--audio-out"), Catch::Contains("--audio-out 'speakers': give none"));
}

TEST_CASE("audio devices: no sound server is a site without sound, not a failed call", "[audio]") {
  // A server address where nothing listens: what a machine without a sound server gives.
  setenv("PULSE_SERVER", "unix:/nonexistent/remotetouch-no-pulse", 1);
  const OpenedInput in = open_audio_input(parse_audio_spec("pulse", "--audio-in"));
  const OpenedOutput out = open_audio_output(parse_audio_spec("pulse:speakers", "--audio-out"));
  unsetenv("PULSE_SERVER");
  CHECK(in.device == nullptr);
  CHECK_THAT(in.description, Catch::StartsWith("no sound in: cannot open the sound server's default input"));
  CHECK(out.device == nullptr);
  CHECK_THAT(out.description, Catch::StartsWith("no sound out: cannot open 'speakers' output"));
  CHECK_THAT(out.description, Catch::Contains("PulseAudio or PipeWire"));
}

TEST_CASE("audio devices: the simulated room echoes the loudspeaker only when asked", "[audio]") {
  const auto speech = audio_devices_tone(kSampleRate / 2, 300.0, 0.3f);
  const auto far = audio_devices_tone(kSampleRate / 2, 700.0, 0.5f);
  for (const bool echo : {false, true}) {
    std::optional<EchoPathOptions> path;
    if (echo) path = EchoPathOptions{.delay_ms = 40.0, .gain_db = -6.0, .reverb_taps = 0};
    SimulatedRoom room(speech, path);
    auto mic = room.microphone();
    auto speaker = room.loudspeaker();
    std::vector<float> block(kBlockSamples), heard;
    for (size_t i = 0; i + kBlockSamples <= far.size(); i += kBlockSamples) {
      speaker->write(std::span(far).subspan(i, kBlockSamples));
      REQUIRE(mic->read(block));
      heard.insert(heard.end(), block.begin(), block.end());
    }
    const auto echo_part = room.echo_heard();
    REQUIRE(echo_part.size() == heard.size());
    if (!echo) {
      for (size_t i = 0; i < heard.size(); ++i) REQUIRE(heard[i] == speech[i]);
      continue;
    }
    const size_t delay = 40 * kSampleRate / 1000;
    for (size_t i = 0; i < delay; ++i) REQUIRE(echo_part[i] == 0.0f);
    for (size_t i = delay; i < heard.size(); i += 97) {
      REQUIRE(echo_part[i] == Approx(0.501187 * far[i - delay]).margin(1e-6));
      REQUIRE(heard[i] == Approx(speech[i] + echo_part[i]).margin(1e-6));
    }
  }
  CHECK_THROWS_WITH(SimulatedRoom({}, EchoPathOptions{.delay_ms = 2.0}), Catch::Contains("outside 10..500 ms"));
  // Reverb: later reflections, each quieter than the direct path.
  const auto taps = echo_taps(EchoPathOptions{});
  REQUIRE(taps.size() == 7);
  for (size_t i = 1; i < taps.size(); ++i) {
    CHECK(taps[i].delay_samples > taps[i - 1].delay_samples);
    CHECK(std::abs(taps[i].gain) < std::abs(taps[0].gain));
  }
}

// Run by tests/sound/live_pulse_test.sh, which starts its own PulseAudio server with a null sink
// (rt_null) on a private socket and points PULSE_SERVER at it: hidden from the plain run.
TEST_CASE("audio devices: live, a tone played to a null sink is heard on its monitor", "[.pulse]") {
  REQUIRE(std::getenv("PULSE_SERVER") != nullptr);
  PulseInputResult in = open_pulse_input("rt_null.monitor");
  INFO(in.message);
  REQUIRE(in.input);
  PulseOutputResult out = open_pulse_output("rt_null");
  INFO(out.message);
  REQUIRE(out.output);
  const auto tone = audio_devices_tone(kSampleRate, 440.0, 0.5f);
  std::vector<float> block(kBlockSamples);
  double loudest = 0.0, tone_power = 0.0, total_power = 0.0;
  // Played and recorded in step, a block each, for three seconds: the tone's second and silence.
  for (size_t i = 0; i < 300; ++i) {
    if ((i + 1) * kBlockSamples <= tone.size()) out.output->write(std::span(tone).subspan(i * kBlockSamples, kBlockSamples));
    REQUIRE(in.input->read(block));
    double power = 0.0, re = 0.0, im = 0.0;
    for (size_t j = 0; j < block.size(); ++j) {
      power += double(block[j]) * block[j];
      const double phase = 2.0 * std::numbers::pi * 440.0 * double(j) / kSampleRate;
      re += block[j] * std::cos(phase);
      im += block[j] * std::sin(phase);
    }
    loudest = std::max(loudest, std::sqrt(power / double(block.size())));
    total_power += power;
    tone_power += 2.0 * (re * re + im * im) / double(block.size());
  }
  WARN("loudest 10 ms RMS on the monitor " << loudest << ", share at 440 Hz " << tone_power / std::max(total_power, 1e-20));
  CHECK(loudest > 0.2);  // the tone's RMS is 0.35
  CHECK(tone_power / total_power > 0.8);
}
