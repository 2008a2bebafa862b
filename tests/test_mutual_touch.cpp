// Mutual touch detection on scripted skeleton pairs (paper: joints within 2 cm of the screen,
// bounding-box overlap above 50 cm^2), with the hysteresis that makes one clap one event pair.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "geometry/site_frames.h"
#include "support/hands.h"
#include "time/monotonic_clock.h"
#include "touch/mutual_touch.h"
#include "touch/touch_loop.h"

using namespace rt;

namespace {

constexpr uint64_t kTickUs = 20'000;  // 50 Hz

// The remote user's hand as they hold it in their own site frame, mapped into ours (site A).
HandSkeleton remote_hand(double x_remote, double y, double z, uint64_t timestamp_us) {
  return map_skeleton(Site::B, Site::A, test::flat_hand(x_remote, y, z, timestamp_us));
}

struct Script {
  std::vector<TouchEvent> events;
  MutualTouchDetector detector;
  uint64_t now = 1'000'000;
  void tick(const std::vector<HandSkeleton>& local, const std::vector<HandSkeleton>& remote) {
    if (auto event = detector.update(now, local, remote)) events.push_back(*event);
    now += kTickUs;
  }
  size_t count(TouchEvent::Kind kind) const {
    size_t n = 0;
    for (const auto& e : events) n += e.kind == kind;
    return n;
  }
};

// Both hands approach from 30 cm, press for half a second, and retract.
void clap(Script& script, double local_x, double remote_x, double y = 0.1) {
  std::vector<double> heights;
  for (double z = 0.3; z > 0.005; z -= 0.02) heights.push_back(z);
  for (int i = 0; i < 25; ++i) heights.push_back(0.005);
  for (double z = 0.005; z < 0.3; z += 0.02) heights.push_back(z);
  for (double z : heights)
    script.tick({test::flat_hand(local_x, y, z, script.now)}, {remote_hand(remote_x, y, z, script.now)});
}

}  // namespace

TEST_CASE("overlapping palms: exactly one start and one end, with timestamps", "[touch]") {
  Script script;
  clap(script, 0.2, -0.2);  // the remote user's -0.2 is our +0.2: the same spot on the glass
  REQUIRE(script.events.size() == 2);
  CHECK(script.events[0].kind == TouchEvent::Kind::Start);
  CHECK(script.events[1].kind == TouchEvent::Kind::End);
  CHECK(script.events[0].overlap_area_m2 > 50e-4);
  CHECK(script.events[0].timestamp_us < script.events[1].timestamp_us);
  CHECK(script.events[0].local_capture_us == script.events[0].timestamp_us);
  CHECK(script.events[0].remote_capture_us == script.events[0].timestamp_us);
}

TEST_CASE("a miss: both palms on the glass, not overlapping", "[touch]") {
  Script script;
  clap(script, 0.2, 0.2);  // both at their own right: 40 cm apart on the shared glass
  CHECK(script.events.empty());
}

TEST_CASE("a graze under the area threshold", "[touch]") {
  Script script;
  // Offset the hands sideways until the contact boxes overlap by less than 50 cm^2.
  const HandSkeleton local = test::flat_hand(0.0, 0.1, 0.005);
  const double full = overlap_area_m2(std::vector{local}, std::vector{remote_hand(0.0, 0.1, 0.005, 0)}, 0.02);
  REQUIRE(full > 50e-4);
  double offset = 0.0;
  while (overlap_area_m2(std::vector{local}, std::vector{remote_hand(-offset, 0.1, 0.005, 0)}, 0.02) > 40e-4)
    offset += 0.002;
  const double graze = overlap_area_m2(std::vector{local}, std::vector{remote_hand(-offset, 0.1, 0.005, 0)}, 0.02);
  CHECK(graze > 0.0);
  CHECK(graze <= 40e-4);
  clap(script, 0.0, -offset);
  CHECK(script.events.empty());
}

TEST_CASE("only one hand at the screen", "[touch]") {
  Script script;
  for (int i = 0; i < 50; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.15, script.now)});
  for (int i = 0; i < 50; ++i) script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {});
  CHECK(script.events.empty());
}

TEST_CASE("tracking lost mid-touch ends the touch once", "[touch]") {
  Script script;
  for (int i = 0; i < 10; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  REQUIRE(script.events.size() == 1);
  for (int i = 0; i < 20; ++i) script.tick({}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  REQUIRE(script.events.size() == 2);
  CHECK(script.events[1].kind == TouchEvent::Kind::End);
  // Started on tick 0, lost from tick 10: the last hand (tick 9's) stands through the dropout
  // hold, then the touch ends on the end_after_ticks-th tick without one.
  const TouchParameters& p = script.detector.parameters();
  const uint64_t ticks_between = 9 + p.dropout_hold_us / kTickUs + uint64_t(p.end_after_ticks);
  CHECK(script.events[1].timestamp_us - script.events[0].timestamp_us == ticks_between * kTickUs);
}

TEST_CASE("a tracker dropout mid-touch, shorter than the hold, neither ends the touch nor starts another", "[touch]") {
  Script script;
  for (int i = 0; i < 10; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  REQUIRE(script.events.size() == 1);
  // Eight ticks (160 ms) without the local hand, then the remote one's, then both again.
  for (int i = 0; i < 8; ++i) script.tick({}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  for (int i = 0; i < 8; ++i) script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {});
  for (int i = 0; i < 10; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  CHECK(script.events.size() == 1);
  // Before a touch nothing is held: a hand that was never seen touching starts nothing.
  Script before;
  before.tick({test::flat_hand(0.2, 0.1, 0.005, before.now)}, {});
  before.tick({}, {remote_hand(-0.2, 0.1, 0.005, before.now)});
  CHECK(before.events.empty());
  // A hold longer than the touch's own hold age makes no sense.
  TouchParameters bad;
  bad.dropout_hold_us = bad.touch_hold_age_us + 1;
  CHECK_THROWS_WITH(MutualTouchDetector(bad), Catch::Contains("dropout_hold_us"));
}

TEST_CASE("a stale skeleton counts as lost tracking", "[touch]") {
  Script script;
  const TouchParameters& parameters = script.detector.parameters();
  const uint64_t frozen = script.now;
  for (int i = 0; i < 5; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, frozen)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  REQUIRE(script.events.size() == 1);
  for (int i = 0; i < 40; ++i)  // the local tracker stops sending: its last skeleton ages
    script.tick({test::flat_hand(0.2, 0.1, 0.005, frozen)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  REQUIRE(script.events.size() == 2);
  CHECK(script.events[1].kind == TouchEvent::Kind::End);
  // Held while the last skeleton is younger than touch_hold_age_us, then end_after_ticks ticks.
  const uint64_t age_at_end = script.events[1].timestamp_us - frozen;
  CHECK(age_at_end > parameters.touch_hold_age_us);
  CHECK(age_at_end <= parameters.touch_hold_age_us + uint64_t(parameters.end_after_ticks) * kTickUs);

  // A stale skeleton cannot start a touch either.
  Script late;
  for (int i = 0; i < 20; ++i)
    late.tick({test::flat_hand(0.2, 0.1, 0.005, late.now)},
              {remote_hand(-0.2, 0.1, 0.005, late.now - parameters.max_skeleton_age_us - 1)});
  CHECK(late.events.empty());
}

TEST_CASE("skeletons late for a moment mid-touch give no second start", "[touch]") {
  // Two site processes on two CPU cores: a remote skeleton can arrive 300 ms late. The palms
  // never left the glass, so the clap stays one touch.
  Script script;
  for (int i = 0; i < 10; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  const uint64_t last_remote = script.now - kTickUs;
  for (int i = 0; i < 15; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.005, last_remote)});
  for (int i = 0; i < 10; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.005, script.now)}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  for (int i = 0; i < 10; ++i)  // then the hands part
    script.tick({test::flat_hand(0.2, 0.1, 0.2, script.now)}, {remote_hand(-0.2, 0.1, 0.2, script.now)});
  REQUIRE(script.events.size() == 2);
  CHECK(script.events[0].kind == TouchEvent::Kind::Start);
  CHECK(script.events[1].kind == TouchEvent::Kind::End);
  CHECK(script.events[1].timestamp_us > script.events[0].timestamp_us + 35 * kTickUs);
}

TEST_CASE("NaN joints are ignored, never a NaN area", "[touch]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  HandSkeleton broken = test::flat_hand(0.2, 0.1, 0.005);
  broken.palm = {nan, nan, nan};
  broken.digits[1][4] = {0.2, nan, 0.0};
  const double area = overlap_area_m2(std::vector{broken}, std::vector{remote_hand(-0.2, 0.1, 0.005, 0)}, 0.02);
  CHECK(std::isfinite(area));
  CHECK(area > 50e-4);  // the other joints still make the box

  HandSkeleton all_nan = broken;
  all_nan.wrist = all_nan.palm;
  for (auto& digit : all_nan.digits)
    for (auto& joint : digit) joint = {nan, nan, nan};
  CHECK_FALSE(contact_box(all_nan, 0.02));
  Script script;
  for (int i = 0; i < 10; ++i) script.tick({all_nan}, {remote_hand(-0.2, 0.1, 0.005, script.now)});
  CHECK(script.events.empty());
}

TEST_CASE("a hand exactly at 2 cm counts; just beyond does not", "[touch]") {
  const HandSkeleton at = test::flat_hand(0.2, 0.1, 0.02);
  const HandSkeleton beyond = test::flat_hand(0.2, 0.1, 0.0201);
  CHECK(contact_box(at, 0.02));
  CHECK_FALSE(contact_box(beyond, 0.02));
  // The remote hand maps to z = -0.02 on our side: the distance is |z|.
  CHECK(contact_box(remote_hand(-0.2, 0.1, 0.02, 0), 0.02));
  Script script;
  for (int i = 0; i < 5; ++i)
    script.tick({test::flat_hand(0.2, 0.1, 0.02, script.now)}, {remote_hand(-0.2, 0.1, 0.02, script.now)});
  CHECK(script.count(TouchEvent::Kind::Start) == 1);
}

TEST_CASE("jitter around the threshold gives no second clap", "[touch]") {
  Script script;
  const HandSkeleton local = test::flat_hand(0.0, 0.1, 0.005);
  // Find offsets whose overlap lies just above and just below 50 cm^2.
  double above = 0.0, below = 0.0;
  for (double offset = 0.0; offset < 0.2; offset += 0.0005) {
    const double area = overlap_area_m2(std::vector{local}, std::vector{remote_hand(-offset, 0.1, 0.005, 0)}, 0.02);
    if (area > 52e-4) above = offset;
    if (area < 48e-4 && area > 30e-4 && below == 0.0) below = offset;
  }
  REQUIRE(above > 0.0);
  REQUIRE(below > above);
  for (int i = 0; i < 60; ++i)
    script.tick({test::flat_hand(0.0, 0.1, 0.005, script.now)},
                {remote_hand(-(i % 2 ? above : below), 0.1, 0.005, script.now)});
  CHECK(script.count(TouchEvent::Kind::Start) == 1);
  CHECK(script.count(TouchEvent::Kind::End) == 0);
}

TEST_CASE("thresholds are parameters, checked", "[touch]") {
  TouchParameters strict;
  strict.start_area_m2 = 500e-4;  // bigger than the hands' boxes
  strict.end_area_m2 = 250e-4;
  Script script{{}, MutualTouchDetector(strict)};
  clap(script, 0.2, -0.2);
  CHECK(script.events.empty());
  TouchParameters bad;
  bad.end_area_m2 = bad.start_area_m2 * 2;
  CHECK_THROWS_WITH(MutualTouchDetector(bad), Catch::Contains("end_area_m2"));
  bad = {};
  bad.joint_distance_m = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(MutualTouchDetector(bad), Catch::Contains("joint_distance_m"));
  bad = {};
  bad.touch_hold_age_us = bad.max_skeleton_age_us - 1;
  CHECK_THROWS_WITH(MutualTouchDetector(bad), Catch::Contains("touch_hold_age_us"));
}

TEST_CASE("the 50 Hz loop hands each event to its callback", "[touch]") {
  std::atomic<int> starts{0};
  TouchLoop loop({}, [&](const TouchEvent& event) { starts += event.kind == TouchEvent::Kind::Start; });
  loop.start();
  // Fresh skeletons, stamped with the loop's clock, kept fresh while we wait.
  for (int i = 0; i < 200 && starts == 0; ++i) {
    const uint64_t now = monotonic_now_us();
    loop.set_local_hands({test::flat_hand(0.2, 0.1, 0.005, now)});
    loop.set_remote_hands({remote_hand(-0.2, 0.1, 0.005, now)});
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  loop.stop();
  CHECK(starts == 1);
  CHECK(loop.ticks() > 0);
}
