// A site's sound end to end: two sites' sound threads over a real session on loopback, each in a
// simulated room that echoes. Site A's sentence must arrive whole in site B's audio.wav, and B's
// echo canceller must take the echo of it down by 20 dB. No GPU: it sits in this half because the
// site library does.
#include <catch2/catch.hpp>

#include <atomic>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "audio/wav_file.h"
#include "media/voice_quality.h"
#include "net/session.h"
#include "net_test_sessions.h"
#include "site/site_sound.h"
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
  CHECK(plain.description() == "in: simulated user; out: simulated loudspeaker");
  site::SiteSound silent({.audio_in = "none", .audio_out = "none"}, Site::A, sim::Effects{}, dir, session,
                         [](const std::string&) {});
  CHECK(silent.description() == "in: no sound in (none asked for); out: no sound out (none asked for)");
  CHECK_THROWS_WITH(site::SiteSound({.audio_in = "microphone"}, Site::A, sim::Effects{}, dir, session, [](const std::string&) {}),
                    Catch::Contains("--audio-in 'microphone'"));
}
