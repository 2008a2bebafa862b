// The site's touch loop (touch/site_touch_loop.h) driven on a simulated clock by a scene's
// simulated trackers, as site_run.cpp drives it: the motor's vibration against the moment the
// scene's true palms meet (touch/scene_contact.h), with contact prediction on and off, at real
// time and at the quarter of it a site plays at on a CPU Vulkan driver.
#include <catch2/catch.hpp>

#include <cstdio>
#include <map>
#include <optional>
#include <vector>

#include "geometry/site_frames.h"
#include "motor/simulated_motor.h"
#include "sim/scene.h"
#include "support/hands.h"
#include "sim/tracker_sim.h"
#include "sim/tracker_space.h"
#include "touch/contact_predictor.h"
#include "touch/scene_contact.h"
#include "touch/site_touch_loop.h"

using namespace rt;

namespace {

struct TrackedFrame {
  uint64_t scene_us = 0;
  std::vector<HandSkeleton> hands;
};

// A scene's tracked frames and true contacts are the same on every play of it, and making them
// (the trackers' hands, the skin sampled every millisecond) is most of a play's time, under the
// sanitizers most of all: each is made once per scene.
const std::vector<TrackedFrame>& tracked(const std::string& scene_name, const sim::Scene& scene, Site site) {
  static std::map<std::pair<std::string, Site>, std::vector<TrackedFrame>> made;
  auto [it, inserted] = made.try_emplace({scene_name, site});
  if (inserted) {
    sim::SimulatedHandTracker tracker = sim::make_simulated_tracker(scene, site);
    while (auto frame = tracker.next_frame())
      it->second.push_back({frame->timestamp_us, sim::skeletons_in_site(*frame, scene.at(site).site.tracker)});
  }
  return it->second;
}

const std::vector<double>& contact_times_s(const std::string& scene_name, const sim::Scene& scene) {
  static std::map<std::string, std::vector<double>> made;
  auto [it, inserted] = made.try_emplace(scene_name);
  if (inserted) it->second = true_contact_times_s(scene);
  return it->second;
}

struct Played {
  nlohmann::json vibration;  // contact_to_vibration_json
  MotorTimingCounts counts;
  size_t pulses_felt = 0;
  std::vector<Gesture> starts;          // the detector's touch starts
  std::vector<Gesture> patterns;        // each motor pattern's gesture, at its first step
  std::vector<motor::MotorCommand> commands;
};

// Site `here` (A unless told) of `scene_name`: its tracker's frames picked up a few milliseconds
// after their capture, the other site's a link's delay later and stamped on a clock of its own,
// the touch loop ticking at 50 Hz.
Played play(const std::string& scene_name, const TouchSettings& settings, double time_scale, Site here = Site::A) {
  const sim::Scene scene = sim::load_scene(sim::resolve_scene(scene_name));
  const Site there = here == Site::A ? Site::B : Site::A;
  const std::vector<TrackedFrame>&local = tracked(scene_name, scene, here), &remote = tracked(scene_name, scene, there);
  auto wall_us = [&](uint64_t scene_us) { return uint64_t(double(scene_us) / time_scale); };
  constexpr uint64_t kPickUpUs = 7'000, kLinkUs = 3'000, kOtherClockUs = 987'654'321;
  uint64_t now_us = 0;
  motor::SimulatedMotor motor([&] { return now_us; },
                              std::chrono::microseconds(uint64_t(settings.motor_latency_ms * 1000.0)));
  Played played;
  SiteTouchLoop touch(
      settings, time_scale,
      [&](const TouchEvent& event) {
        if (event.kind == TouchEvent::Kind::Start) played.starts.push_back(event.gesture);
      },
      [&](MotorCue cue, uint64_t, const MotorStep& step, Gesture gesture) {
        if (cue == MotorCue::Pulse) {
          if (step.after.count() == 0) played.patterns.push_back(gesture);
          (void)motor.pulse(step.duration, step.strength);
        } else {
          (void)motor.stop();
        }
      });
  size_t next_local = 0, next_remote = 0;
  const uint64_t end_us = wall_us(uint64_t(scene.duration_s() * 1e6)) + 500'000;
  for (now_us = 13'000; now_us < end_us;) {
    std::optional<size_t> newest_local, newest_remote;
    while (next_local < local.size() && wall_us(local[next_local].scene_us) + kPickUpUs <= now_us) newest_local = next_local++;
    while (next_remote < remote.size() && wall_us(remote[next_remote].scene_us) + kPickUpUs + kLinkUs <= now_us)
      newest_remote = next_remote++;
    if (newest_local) {
      std::vector<HandSkeleton> hands = local[*newest_local].hands;
      for (HandSkeleton& hand : hands) hand.timestamp_us = wall_us(local[*newest_local].scene_us);
      touch.set_local_hands(hands);
    }
    if (newest_remote) {
      const uint64_t captured_us = wall_us(remote[*newest_remote].scene_us);
      std::vector<HandSkeleton> hands;
      for (const HandSkeleton& hand : remote[*newest_remote].hands) hands.push_back(map_skeleton(there, here, hand));
      touch.set_remote_hands(hands, captured_us + kOtherClockUs, captured_us + kPickUpUs + kLinkUs);
    }
    touch.loop().tick(now_us);
    const uint64_t next_tick_us = now_us + 20'000;
    if (const std::optional<uint64_t> due = touch.loop().pulse_due_us(); due && *due < next_tick_us) {
      now_us = std::max(now_us, *due);
      touch.loop().fire_due(now_us);
    }
    now_us = next_tick_us;
  }
  std::vector<uint64_t> contacts_us;
  for (const double t : contact_times_s(scene_name, scene)) contacts_us.push_back(wall_us(uint64_t(t * 1e6)));
  played.commands = motor.commands();
  const std::vector<uint64_t> felt = motor.felt_pulse_starts();
  played.vibration = contact_to_vibration_json(contacts_us, felt, uint64_t(500'000 / time_scale));
  played.counts = touch.loop().motor_counts();
  played.pulses_felt = felt.size();
  return played;
}

TouchSettings with_prediction(bool on) {
  TouchSettings settings;
  settings.contact_prediction = on;
  return settings;
}

}  // namespace

TEST_CASE("the clap's palms meet once, when both reach the glass") {
  const sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  const std::vector<double> contacts = contact_times_s("clap", scene);
  REQUIRE(contacts.size() == 1);
  // B starts 0.2 s later, so B's palm decides: after its raise, approach and press.
  CHECK(contacts[0] > 2.0);
  CHECK(contacts[0] < 3.0);
  for (const char* scene_name : {"miss", "wave", "graze"})
    CHECK(contact_times_s(scene_name, sim::load_scene(sim::resolve_scene(scene_name))).empty());
}

TEST_CASE("the site's motor vibrates as the clap's palms meet with prediction, at the detector's band without") {
  for (const double time_scale : {1.0, 0.25}) {
    const Played off = play("clap", with_prediction(false), time_scale);
    const Played on = play("clap", with_prediction(true), time_scale);
    std::printf("clap at time scale %.2f: contact to vibration without prediction %s, with %s; pulses predicted %llu "
                "confirmed %llu cancelled %llu unpredicted %llu\n",
                time_scale, off.vibration.dump().c_str(), on.vibration.dump().c_str(),
                (unsigned long long)on.counts.predicted, (unsigned long long)on.counts.confirmed,
                (unsigned long long)on.counts.cancelled, (unsigned long long)on.counts.unpredicted);
    CAPTURE(time_scale, off.vibration.dump(), on.vibration.dump());
    REQUIRE(on.vibration["contacts"] == 1);
    REQUIRE(on.vibration["contacts_not_felt"] == 0);
    REQUIRE(off.vibration["contacts_not_felt"] == 0);
    CHECK(on.pulses_felt == 1);
    CHECK(off.pulses_felt == 1);
    CHECK(on.counts.predicted == 1);
    CHECK(on.counts.cancelled == 0);
    CHECK(off.counts.predicted == 0);
    // The scene's press slows onto the glass, so the detector's 2 cm band sees the touch early;
    // at real time that happens to cancel the motor's latency, at a quarter of it (a CPU
    // driver's) the vibration comes a quarter of a second early. The prediction times the
    // palm's arrival instead: within a tracker frame of the scene's clock either way.
    const double on_ms = on.vibration["median_ms"].get<double>(), off_ms = off.vibration["median_ms"].get<double>();
    CHECK(std::abs(on_ms) <= 0.025e3 / time_scale);
    if (time_scale < 1) CHECK(std::abs(on_ms) < 0.5 * std::abs(off_ms));
  }
}

TEST_CASE("the site's motor stays still where the palms do not meet") {
  for (const char* scene : {"miss", "wave", "graze"})
    for (const bool predict : {false, true})
      for (const double time_scale : {1.0, 0.25}) {
        const Played played = play(scene, with_prediction(predict), time_scale);
        CAPTURE(scene, predict, time_scale, played.vibration.dump());
        CHECK(played.pulses_felt == 0);
        CHECK(played.counts.predicted == 0);
        CHECK(played.counts.unpredicted == 0);
      }
}

TEST_CASE("each scene's touch is its own gesture at both sites, with that gesture's motor pattern") {
  const std::vector<std::pair<std::string, std::vector<Gesture>>> expected = {
      // approach: A's hand stops 6 cm before the glass, so no rule sees a touch (nor the paper's).
      // noisy-clap: its tracker's dropouts during the hold do not end the touch.
      {"clap", {Gesture::Palm}},           {"noisy-clap", {Gesture::Palm}}, {"approach", {}},
      {"fist-bump", {Gesture::Fist}},
      {"finger-touch", {Gesture::Finger}}, {"miss", {}},               {"wave", {}},
      {"graze", {}}};
  for (const auto& [scene, gestures] : expected)
    for (const Site site : {Site::A, Site::B})
      for (const bool predict : {true, false}) {
        const Played played = play(scene, with_prediction(predict), 1.0, site);
        CAPTURE(scene, site_name(site), predict, played.vibration.dump());
        REQUIRE(played.starts.size() == gestures.size());
        REQUIRE(played.patterns.size() == gestures.size());
        size_t steps = 0;
        for (size_t i = 0; i < gestures.size(); ++i) {
          CHECK(gesture_name(played.starts[i]) == std::string(gesture_name(gestures[i])));
          CHECK(gesture_name(played.patterns[i]) == std::string(gesture_name(gestures[i])));
          steps += motor_pattern(gestures[i]).size();
        }
        // Every step of the pattern was commanded and felt, nothing else, and no pulse was cancelled.
        CHECK(played.pulses_felt == steps);
        CHECK(played.counts.cancelled == 0);
        CHECK(played.vibration["vibrations_without_contact"] == 0);
        CHECK(played.vibration["contacts_not_felt"] == 0);
        CHECK(played.vibration["contacts"] == gestures.size());
        if (!gestures.empty()) {
          // The pattern as the gesture's: its steps' lengths and strengths, in order.
          const std::vector<MotorStep>& pattern = motor_pattern(gestures.front());
          size_t step = 0;
          for (const motor::MotorCommand& command : played.commands)
            if (command.kind == motor::MotorCommand::Kind::Pulse && step < pattern.size()) {
              CHECK(command.duration == pattern[step].duration);
              CHECK(command.strength == pattern[step].strength);
              ++step;
            }
          CHECK(step == pattern.size());
        }
      }
}

TEST_CASE("the gestures' motor patterns differ: one long pulse, a strong double, a light tick") {
  const auto& palm = motor_pattern(Gesture::Palm);
  const auto& fist = motor_pattern(Gesture::Fist);
  const auto& finger = motor_pattern(Gesture::Finger);
  REQUIRE(palm.size() == 1);
  CHECK(palm[0].duration == std::chrono::milliseconds(150));
  REQUIRE(fist.size() == 2);
  CHECK(fist[0].duration < palm[0].duration);
  CHECK(fist[0].strength > palm[0].strength);
  CHECK(fist[1].after >= fist[0].duration);  // two knocks, not one long one
  REQUIRE(finger.size() == 1);
  CHECK(finger[0].duration < fist[0].duration);
  CHECK(finger[0].strength < palm[0].strength);
  for (const Gesture gesture : {Gesture::Palm, Gesture::Fist, Gesture::Finger}) {
    CHECK(gesture_from_name(gesture_name(gesture)) == gesture);
    CHECK(motor_pattern(gesture).front().after.count() == 0);
  }
  CHECK_FALSE(gesture_from_name("slap").has_value());
}

TEST_CASE("a remote clock maps the other site's stamps by the link's least delay") {
  RemoteClock clock;
  // Captured at 1000, 21000, 41000 here; stamped 5e9 later on the other clock; 3 ms, then 9 ms of link.
  CHECK(clock.to_local(5'000'001'000, 4'000) == 4'000);
  CHECK(clock.to_local(5'000'021'000, 30'000) == 24'000);  // a slow arrival keeps its stamp's spacing
  CHECK(clock.to_local(5'000'041'000, 43'000) == 43'000);
}

TEST_CASE("the site's touch settings refuse what makes no sense") {
  TouchSettings settings;
  CHECK_THROWS_WITH(config::read_knobs_json(touch_knobs(), nlohmann::json{{"motor_latency_ms", -5}}, settings, "site.json: 'touch'"),
                    Catch::Contains("motor_latency_ms") && Catch::Contains("[0, 1000]"));
  CHECK_THROWS_WITH(config::read_knobs_json(touch_knobs(), nlohmann::json{{"contact_prediction", "maybe"}}, settings, "x"),
                    Catch::Contains("one of on, off"));
  config::read_knobs_json(touch_knobs(), nlohmann::json{{"contact_prediction", "off"}, {"motor_latency_ms", 45}}, settings, "x");
  CHECK_FALSE(settings.contact_prediction);
  CHECK(site_motor_timing(settings, 1.0).motor_spin_up_us == 45'000);
  CHECK_THROWS(site_motor_timing(settings, 0.0));
}
TEST_CASE("figures: contact to vibration per scene", "[.figures]") {
  for (const char* scene : {"clap", "approach", "noisy-clap", "train-fast-reach", "fist-bump", "finger-touch"})
    for (const double time_scale : {1.0, 0.25})
      for (const bool predict : {false, true}) {
        const Played p = play(scene, with_prediction(predict), time_scale);
        std::printf("%-16s scale %.2f prediction %-3s: contacts %d felt %d, median %s ms; pulses predicted %llu cancelled %llu "
                    "unpredicted %llu, stray %d\n",
                    scene, time_scale, predict ? "on" : "off", p.vibration["contacts"].get<int>(),
                    p.vibration["contacts"].get<int>() - p.vibration["contacts_not_felt"].get<int>(),
                    p.vibration["median_ms"].dump().c_str(), (unsigned long long)p.counts.predicted,
                    (unsigned long long)p.counts.cancelled, (unsigned long long)p.counts.unpredicted,
                    p.vibration["vibrations_without_contact"].get<int>());
      }
}

TEST_CASE("a side whose samples stopped coming predicts no contact") {
  // Both palms reach for the glass at 0.5 m/s, due there at 100 ms; the remote one behind it.
  ContactPredictor predictor;
  for (uint64_t t = 0; t <= 40'000; t += 10'000) {
    const double z = 0.5 * (0.1 - double(t) * 1e-6);
    predictor.add_local({rt::test::flat_hand(0, 0, z, t)});
    predictor.add_remote({rt::test::flat_hand(0, 0, -z, t)});
  }
  REQUIRE(predictor.predicted_contact_us(40'000).has_value());
  CHECK(std::llabs(int64_t(*predictor.predicted_contact_us(40'000)) - 100'000) < 2'000);
  CHECK_FALSE(predictor.predicted_contact_us(40'000 + ContactPredictionParameters{}.max_sample_age_us + 1).has_value());
}
