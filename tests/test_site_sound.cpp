// A site's sound end to end: two sites' sound threads over a real session on loopback, each in a
// simulated room that echoes. Site A's sentence must arrive whole in site B's audio.wav, and B's
// echo canceller must take the echo of it down by 20 dB. No GPU: it sits in this half because the
// site library does.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "audio/wav_file.h"
#include "media/voice_quality.h"
#include "net/session.h"
#include "net_test_sessions.h"
#include "site/site_sound.h"
#include "time/monotonic_clock.h"
#include "support/output_dir.h"

using namespace rt;
using namespace std::chrono_literals;

TEST_CASE("site sound: A's sentence arrives whole at B, and B cancels its room's echo", "[sound]") {
  const auto dir = test::output_dir("test_site_sound");
  std::filesystem::remove_all(dir);
  for (const char* site : {"A", "B"}) std::filesystem::create_directories(dir / site);
  const net::SessionKey key = net::random_session_key();
  test::LogLines log;
  // The site hands each voice frame its transport receives to its sound (site_run.cpp).
  std::atomic<site::SiteSound*> a_sound{nullptr}, b_sound{nullptr};
  auto voice_to = [](std::atomic<site::SiteSound*>& sound) {
    return [&sound](const net::Message& message) {
      site::SiteSound* to = sound.load();
      if (const auto* voice = std::get_if<net::VoiceMessage>(&message); voice && to) to->receive(*voice);
    };
  };
  net::Session a_session(test::test_session_options(net::Role::Listener, key, log, "A"));
  a_session.set_handler(voice_to(a_sound));
  a_session.start();
  net::SessionOptions connector = test::test_session_options(net::Role::Connector, key, log, "B");
  connector.port = a_session.local_port();
  net::Session b_session(connector);
  b_session.set_handler(voice_to(b_sound));
  b_session.start();
  REQUIRE(b_session.wait_connected(5000ms));

  sim::Effects echoing;
  echoing.room_echo = sim::RoomEcho{};
  std::vector<std::string> lines;
  auto sink = [&](const std::string& line) { lines.push_back(line); };
  site::SiteSound a({}, Site::A, echoing, dir / "A", a_session, sink);
  site::SiteSound b({}, Site::B, echoing, dir / "B", b_session, sink);
  a_sound = &a;
  b_sound = &b;
  a.start();
  b.start();
  // A speaks from 0.5 s for about 4.5 s; B answers only at 6 s.
  std::this_thread::sleep_for(std::chrono::milliseconds(int(site::simulated_sentence_start_s(Site::B) * 1000)));
  a.stop();
  b.stop();
  a_session.stop();
  b_session.stop();
  a_sound = nullptr;
  b_sound = nullptr;
  INFO("sound log: " << (lines.empty() ? std::string("(empty)") : lines.front()));
  CHECK(lines.empty());

  const nlohmann::json m = b.metrics();
  INFO(m.dump(2));
  REQUIRE(m.contains("echo"));
  CHECK(m["echo"]["erle_db_after_2s"].get<double>() >= 20.0);
  CHECK(m["echo"]["echo_only_seconds"].get<double>() >= 1.0);
  CHECK(m["voice"]["bitrate_kbps"].get<double>() == Approx(28.0).margin(1.0));
  CHECK(m["audio_wav"]["start_us"].get<uint64_t>() > 0);

  const auto said = site::speak_with_espeak(site::simulated_sentence(Site::A), dir);
  const auto heard = audio::read_wav_file((dir / "B" / "audio.wav").string());
  const media::EnvelopeMatch match = media::envelope_match(said, heard, 2.0);
  WARN("A's sentence at B: envelope correlation " << match.correlation << " at " << match.lag_ms << " ms");
  CHECK(match.correlation >= 0.9);
  CHECK(match.lag_ms >= 500.0);  // said from 0.5 s, and the jitter buffer's 60 ms on top
  CHECK(match.lag_ms <= 800.0);
}

TEST_CASE("site sound: no echo unless the scene asks, and none asked is a silent site", "[sound]") {
  const auto dir = test::output_dir("test_site_sound") / "quiet";
  std::filesystem::create_directories(dir);
  const net::SessionKey key = net::random_session_key();
  test::LogLines log;
  net::Session session(test::test_session_options(net::Role::Listener, key, log, "A"));
  site::SiteSound plain({}, Site::A, sim::Effects{}, dir, session, [](const std::string&) {});
  CHECK_FALSE(plain.metrics().contains("echo"));
  CHECK(plain.description() == "in: simulated user; out: simulated loudspeakers (stereo)");
  site::SiteSound silent({.audio_in = "none", .audio_out = "none"}, Site::A, sim::Effects{}, dir, session,
                         [](const std::string&) {});
  CHECK(silent.description() == "in: no sound in (none asked for); out: no sound out (none asked for)");
  CHECK_THROWS_WITH(site::SiteSound({.audio_in = "microphone"}, Site::A, sim::Effects{}, dir, session, [](const std::string&) {}),
                    Catch::Contains("--audio-in 'microphone'"));
}

TEST_CASE("site sound: a touch's sound starts at the sample asked for, from where the palms meet", "[sound][touch]") {
  const auto dir = test::output_dir("test_site_sound") / "touch";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const net::SessionKey key = net::random_session_key();
  test::LogLines log;
  net::Session session(test::test_session_options(net::Role::Listener, key, log, "A"));
  // No microphone: the loudspeakers play silence but for the touch sounds.
  site::SiteSound sound({.audio_in = "none"}, Site::A, sim::Effects{}, dir, session, [](const std::string&) {});
  sound.start();
  std::this_thread::sleep_for(100ms);
  const media::StereoPlacement to_the_right = media::place_between_loudspeakers({0.3, 0.0, 0.0}, {0.0, 0.0, 0.6});
  // Ahead (a predicted contact), already past (a touch seen late), and one withdrawn in time.
  const uint64_t ahead_us = monotonic_now_us() + 80'000;
  sound.play_touch_sound(media::TouchSound::Clap, ahead_us, to_the_right);
  const uint64_t withdrawn = sound.play_touch_sound(media::TouchSound::FistBump, monotonic_now_us() + 250'000, {});
  std::this_thread::sleep_for(30ms);
  sound.cancel_touch_sound(withdrawn);
  std::this_thread::sleep_for(370ms);
  const uint64_t past_us = monotonic_now_us() - 30'000;
  sound.play_touch_sound(media::TouchSound::FingerTap, past_us, {});
  // The far voice aims past the far portrait's latency, into the middle of the lip-sync window.
  sound.hold_voice_to(100.0);
  std::this_thread::sleep_for(300ms);
  sound.stop();

  const nlohmann::json m = sound.metrics();
  INFO(m.dump(2));
  const nlohmann::json& sounds = m["touch_sounds"]["sounds"];
  REQUIRE(sounds.size() == 3);
  CHECK(sounds[0]["late_ms"].get<double>() == Approx(0.0).margin(0.05));
  CHECK(sounds[1]["cancelled"].get<bool>());
  CHECK(m["voice"]["held_to_the_portrait"]["held_to_ms"].get<double>() == Approx(140.0));
  // A past onset starts with the next block made, never in what has already played: late by what
  // was past plus at most a block and the thread's wake-up. A thread that runs behind its blocks
  // (a loaded machine) makes blocks whose time to play has come already, so the lateness can read
  // less than what was past, but never nothing.
  CHECK(sounds[2]["late_ms"].get<double>() > 0.0);
  CHECK(sounds[2]["late_ms"].get<double>() <= 30.0 + 10.0 + 5.0);

  // Listened to: the file holds each sound where the metrics say, and nothing else.
  const uint64_t file_start_us = m["audio_wav"]["start_us"].get<uint64_t>();
  const std::vector<float> stereo = audio::read_wav_file((dir / "audio.wav").string(), 10.0, 2);
  REQUIRE(stereo.size() / 2 >= sounds[2]["onset_sample"].get<size_t>() + 480);
  std::vector<size_t> onsets_left, onsets_right;
  for (int channel = 0; channel < 2; ++channel) {
    bool in_sound = false;
    size_t quiet = 0;
    for (size_t i = 0; i < stereo.size() / 2; ++i) {
      const bool loud = std::abs(stereo[2 * i + size_t(channel)]) > 0.01f;
      if (loud && !in_sound) (channel == 0 ? onsets_left : onsets_right).push_back(i);
      quiet = loud ? 0 : quiet + 1;
      in_sound = loud || (in_sound && quiet < 2400);  // a sound ends after 50 ms of quiet
    }
  }
  REQUIRE(onsets_right.size() == 2);  // the clap and the tap: the fist bump was withdrawn
  REQUIRE(onsets_left.size() == 2);
  const double clap_onset_ms = double(onsets_right[0]) / 48.0;
  const double expected_ms = (double(ahead_us) - double(file_start_us)) / 1000.0;
  WARN("clap onset in audio.wav " << clap_onset_ms - expected_ms << " ms from the time asked for");
  // The file's clock: its first sample plays when its block is due.
  CHECK(std::abs(clap_onset_ms - expected_ms) <= 1.0);
  CHECK(onsets_right[0] <= sounds[0]["onset_sample"].get<size_t>() + 48);
  CHECK(onsets_right[0] + 1 >= sounds[0]["onset_sample"].get<size_t>());
  // From the right: the left ear later by the head's path, and softer.
  CHECK(onsets_left[0] >= onsets_right[0] + to_the_right.delay_left_samples);
  CHECK(onsets_left[0] <= onsets_right[0] + to_the_right.delay_left_samples + 48);
  double left_power = 0, right_power = 0;
  for (size_t i = onsets_right[0]; i < onsets_right[0] + 4800; ++i) {
    left_power += double(stereo[2 * i]) * stereo[2 * i];
    right_power += double(stereo[2 * i + 1]) * stereo[2 * i + 1];
  }
  CHECK(10.0 * std::log10(right_power / left_power) == Approx(20.0 * std::log10(to_the_right.gain_right / to_the_right.gain_left)).margin(0.5));
  CHECK(onsets_right[1] >= sounds[2]["onset_sample"].get<size_t>());
  CHECK(onsets_right[1] <= sounds[2]["onset_sample"].get<size_t>() + 48);
}
