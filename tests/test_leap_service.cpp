// The live Leap tracker (devices/tracker/leap_service.h) against a fake Leap service started by the
// test on loopback: it greets as the service does, checks the client's two requests, then replays
// the clap's tracker frames (as tracker.jsonl holds them) with garbage, a malformed frame and an
// oversized message among them. The client keeps the newest frame, counts and survives the bad
// messages (the oversized one ends the connection, and it reconnects), comes back after the
// service stops and restarts on the same port, and says clearly when no service answers.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <thread>

#include "config/assets.h"
#include "sim/leap_json.h"
#include "support/fake_leap_service.h"
#include "sim/scene.h"
#include "sim/tracker_sim.h"
#include "sim/tracker_space.h"
#include "tracker/leap_service.h"

using namespace rt;
using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using test::FakeLeapService;
using test::LeapSocket;
using test::greet;
using test::hold;

namespace {

const std::filesystem::path kScenes = rt::config::assets_dir() / "scenes";

std::vector<std::string> clap_lines() {
  sim::SimulatedHandTracker tracker = sim::make_simulated_tracker(sim::load_scene(kScenes / "clap.json"), Site::A);
  std::vector<std::string> lines;
  while (auto frame = tracker.next_frame())
    if (!frame->hands.empty()) lines.push_back(sim::leap_json_line(*frame));
  return lines;
}

// How long a test waits for what must happen: far beyond what it takes on a 2-core CI runner
// shared with other tests, so that only what never happens fails a test, never a slow machine.
constexpr std::chrono::milliseconds kPatience = 20000ms;

template <typename Predicate>
bool eventually(Predicate predicate, std::chrono::milliseconds timeout = kPatience) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (predicate()) return true;
    std::this_thread::sleep_for(5ms);
  }
  return predicate();
}

// Watches the tracker's newest frame while a test waits: every one seen must be the frame the
// service sent as that sequence number (`sent(sequence)`, none when it sent fewer), and the
// numbers never go back. A frame lost, doubled or out of order shows as a newest frame that is
// not the one sent as its number.
struct NewestFrames {
  using Sent = std::function<const std::string*(uint64_t sequence)>;
  NewestFrames(const devices::LeapServiceTracker& tracker, Sent sent) : tracker(tracker), sent(std::move(sent)) {}
  const devices::LeapServiceTracker& tracker;
  Sent sent;
  uint64_t last_sequence = 0;
  bool in_order = true;
  std::string wrong;
  void look() {
    const auto newest = tracker.newest();
    if (!newest || newest->sequence == last_sequence) return;
    const std::string* line = sent(newest->sequence);
    if (newest->sequence < last_sequence || !line || newest->frame != sim::parse_leap_json_line(*line)) {
      if (in_order) wrong = "frame " + std::to_string(newest->sequence) + " after " + std::to_string(last_sequence) +
                            " is not the frame sent as that one";
      in_order = false;
    }
    last_sequence = newest->sequence;
  }
};

devices::LeapServiceTracker::Options client_options(uint16_t port) {
  devices::LeapServiceTracker::Options options;
  options.url = "ws://127.0.0.1:" + std::to_string(port) + "/v6.json";
  options.reconnect_delay = 50ms;
  options.max_message_bytes = 64 * 1024;
  return options;
}

}  // namespace

TEST_CASE("Leap service URLs: defaults, and clear errors", "[tracker]") {
  const devices::LeapUrl url = devices::parse_leap_url("ws://127.0.0.1");
  CHECK(url.text() == "ws://127.0.0.1:6437/v6.json");
  CHECK(devices::parse_leap_url("ws://leap.local:7000/v7.json").text() == "ws://leap.local:7000/v7.json");
  CHECK_THROWS_WITH(devices::parse_leap_url("http://127.0.0.1:6437"), Contains("must start with ws://"));
  CHECK_THROWS_WITH(devices::parse_leap_url("ws://:6437/v6.json"), Contains("has no host"));
  CHECK_THROWS_WITH(devices::parse_leap_url("ws://127.0.0.1:99999/v6.json"), Contains("port must be a number"));
  CHECK_THROWS_WITH(devices::parse_leap_url("ws://127.0.0.1:x/v6.json"), Contains("port must be a number"));
  CHECK_THROWS_WITH(devices::parse_leap_url("ws://127.0.0.1:6437/v6 .json"), Contains("space"));
}

TEST_CASE("the live tracker reads the service's frames and survives bad messages", "[tracker]") {
  const std::vector<std::string> lines = clap_lines();
  REQUIRE(lines.size() > 20);
  std::vector<std::string> requests;
  std::atomic<bool> sent_all{false};
  FakeLeapService service(0, [&](LeapSocket& ws) {
    if (sent_all) {  // after the oversized message: a second connection gets the rest, once
      greet(ws);
      test::send_text(ws, lines.back());
      hold(ws);
      return;
    }
    greet(ws, &requests);
    for (size_t i = 0; i + 1 < lines.size(); ++i) {
      test::send_text(ws, lines[i]);
      if (i == 3) test::send_text(ws, "not json at all {");
      if (i == 5) test::send_text(ws, R"({"id": 9, "timestamp": 5, "hands": [{"id": 4}], "pointables": []})");
      if (i == 7) test::send_text(ws, R"({"event": {"type": "deviceEvent"}})");
    }
    sent_all = true;
    test::send_text(ws, std::string(100 * 1024, ' '));  // over the client's bound
    hold(ws);  // until the client drops the connection over it
  });

  devices::LeapServiceTracker tracker(client_options(service.port()));
  tracker.wait_connected(kPatience);
  // The first connection's frames are lines 1 to n-1, the second's line n.
  NewestFrames newest_frames{tracker, [&](uint64_t sequence) { return sequence <= lines.size() ? &lines[sequence - 1] : nullptr; }};
  REQUIRE(eventually([&] {
    newest_frames.look();
    return tracker.status().connections >= 2 && tracker.status().frames >= lines.size();
  }));
  INFO(newest_frames.wrong);
  CHECK(newest_frames.in_order);
  // Each frame sent once, and the second connection held: no frame comes twice, none more.
  const devices::LeapServiceStatus status = tracker.status();
  CHECK(requests == std::vector<std::string>{R"({"background": true})", R"({"focused": true})"});
  CHECK(status.connections == 2);
  CHECK(status.frames == lines.size());
  CHECK(status.frames_with_hands == lines.size());
  CHECK(status.messages_malformed == 2);
  CHECK(status.messages_oversized == 1);
  CHECK(status.messages_other >= 3);  // the greetings and the event
  CHECK(status.service_version == "fake-4.1.0");
  const auto newest = tracker.newest();
  REQUIRE(newest);
  CHECK(newest->frame == sim::parse_leap_json_line(lines.back()));
  CHECK(newest->sequence == lines.size());
  // In the site frame through the tracker's placement, as the site maps it.
  const auto site = sim::skeletons_in_site(newest->frame, sim::TrackerPlacement{});
  REQUIRE(site.size() == newest->frame.hands.size());
  CHECK(site[0].wrist.allFinite());
  CHECK(status.to_json()["messages_refused"]["oversized"] == 1);
  REQUIRE(status.frames_per_second());
  CHECK(*status.frames_per_second() > 0);
  CHECK(tracker.status().last_frame_us >= tracker.status().first_frame_us);
}

TEST_CASE("the live tracker reconnects when the service stops and comes back", "[tracker]") {
  const std::vector<std::string> lines = clap_lines();
  uint16_t port = 0;
  // Five frames on each connection, which the service then holds until it stops: the client
  // reconnects only because the service went away.
  auto script = [&](LeapSocket& ws) {
    greet(ws);
    for (int i = 0; i < 5; ++i) test::send_text(ws, lines[size_t(i)]);
    hold(ws);
  };
  auto first = std::make_unique<FakeLeapService>(0, script);
  port = first->port();
  devices::LeapServiceTracker tracker(client_options(port));
  NewestFrames newest_frames{tracker, [&](uint64_t sequence) { return sequence <= 10 ? &lines[(sequence - 1) % 5] : nullptr; }};
  tracker.wait_connected(kPatience);
  REQUIRE(eventually([&] {
    newest_frames.look();
    return tracker.status().frames >= 5;
  }));
  first.reset();  // the service stops
  REQUIRE(eventually([&] { return tracker.status().state != devices::LeapState::Connected; }));
  CHECK_FALSE(tracker.status().last_error.empty());
  const devices::LeapServiceStatus before = tracker.status();
  CHECK(before.connections == 1);
  CHECK(before.frames == 5);
  FakeLeapService second(port, script);  // and comes back on the same port
  REQUIRE(eventually([&] {
    newest_frames.look();
    return tracker.status().connections > before.connections && tracker.status().frames >= before.frames + 5;
  }));
  INFO(newest_frames.wrong);
  CHECK(newest_frames.in_order);
  CHECK(tracker.status().frames == 10);
  CHECK(tracker.status().state == devices::LeapState::Connected);
}

TEST_CASE("no service: a clear error at once, and stopping never hangs", "[tracker]") {
  uint16_t port = 0;
  {
    FakeLeapService probe(0, [](auto&) {});
    port = probe.port();
  }  // nothing listens there now
  devices::LeapServiceTracker tracker(client_options(port));
  // The first attempt is refused as soon as the client's thread makes it: waited for, so that the
  // error below names the refusal however late a loaded machine runs that thread.
  REQUIRE(eventually([&] { return !tracker.status().last_error.empty(); }));
  const auto asked = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(tracker.wait_connected(500ms),
                    Contains("no Leap service answers at ws://127.0.0.1:" + std::to_string(port) + "/v6.json") &&
                        Contains("refused"));
  CHECK(std::chrono::steady_clock::now() - asked < 2s);  // its own timeout, not a connect timeout (2 s) after it
  CHECK(tracker.status().state == devices::LeapState::Connecting);
  CHECK(tracker.status().connections == 0);
  CHECK_FALSE(tracker.newest());
  CHECK_FALSE(tracker.status().frames_per_second());
  CHECK(tracker.status().to_json()["frames_per_second"].is_null());
}
