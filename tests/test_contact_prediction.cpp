// Contact prediction (touch/contact_predictor.h) and the motor's timing in the touch loop
// (touch/touch_loop.h), on scripted reaches with an exact, known contact.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "support/hands.h"
#include "touch/contact_predictor.h"
#include "touch/touch_loop.h"

using namespace rt;
using rt::test::flat_hand;

namespace {

// A reach's distance to the glass at time t (seconds).
using Path = std::function<double(double)>;

// Constant speed v (m/s) from z0, reaching the glass at `contact_s`.
Path steady(double contact_s, double v) {
  return [=](double t) { return std::max(0.0, v * (contact_s - t)); };
}
// Slowing down at a constant rate: speed v_end on reaching the glass at `contact_s`, a the deceleration.
Path slowing(double contact_s, double v_end, double a) {
  return [=](double t) {
    const double s = contact_s - t;  // time left
    return s <= 0 ? 0.0 : v_end * s + 0.5 * a * s * s;
  };
}

uint64_t us(double s) { return uint64_t(std::llround(s * 1e6)); }

// Feeds both sides' samples every 10 ms up to `until_s` and asks for the contact then.
std::optional<uint64_t> predict(const Path& local, const Path& remote, double until_s, double local_x = 0.0,
                                double remote_x = 0.0, const ContactPredictionParameters& parameters = {}) {
  ContactPredictor predictor(parameters);
  for (double t = 0.0; t <= until_s + 1e-9; t += 0.01) {
    predictor.add_local({flat_hand(local_x, 0.0, local(t), us(t))});
    predictor.add_remote({flat_hand(remote_x, 0.0, remote(t), us(t))});
  }
  return predictor.predicted_contact_us(us(until_s));
}

}  // namespace

TEST_CASE("a steady reach and a slowing one: the contact is predicted to the millisecond") {
  const auto both_steady = predict(steady(0.50, 0.6), steady(0.50, 0.6), 0.42);
  REQUIRE(both_steady);
  CHECK(std::abs(double(*both_steady) - 500'000.0) < 1000.0);
  // Slowing at 3 m/s^2 to 0.3 m/s on arrival: a straight line through the same samples would
  // predict about 20 ms early.
  const auto both_slowing = predict(slowing(0.50, 0.3, 3.0), slowing(0.50, 0.3, 3.0), 0.42);
  REQUIRE(both_slowing);
  CHECK(std::abs(double(*both_slowing) - 500'000.0) < 1000.0);
}

TEST_CASE("the later palm decides the contact") {
  const auto contact = predict(steady(0.45, 0.6), slowing(0.52, 0.4, 2.0), 0.40);
  REQUIRE(contact);
  CHECK(std::abs(double(*contact) - 520'000.0) < 1000.0);
  // One palm already on the glass: the other's arrival.
  const auto one_there = predict(steady(0.30, 0.6), steady(0.48, 0.6), 0.40);
  REQUIRE(one_there);
  CHECK(std::abs(double(*one_there) - 480'000.0) < 1000.0);
}

TEST_CASE("no contact is predicted for what must not vibrate") {
  // Hover: slowing to a stop 3 cm in front of the glass.
  const Path hover = [](double t) { return 0.03 + std::max(0.0, 0.5 * 2.0 * std::pow(std::max(0.0, 0.5 - t), 2)); };
  CHECK_FALSE(predict(hover, hover, 0.42));
  // Miss: both reach the glass, 30 cm apart.
  CHECK_FALSE(predict(steady(0.5, 0.6), steady(0.5, 0.6), 0.42, -0.15, 0.15));
  // Graze: 11 cm apart, the two hands' outlines 2 cm apart.
  CHECK_FALSE(predict(steady(0.5, 0.6), steady(0.5, 0.6), 0.42, 0.0, 0.11));
  // Moving away, and holding still in front of the glass.
  CHECK_FALSE(predict([](double t) { return 0.05 + 0.5 * t; }, steady(0.5, 0.6), 0.42));
  CHECK_FALSE(predict([](double) { return 0.10; }, steady(0.5, 0.6), 0.42));
  // Further ahead than the horizon: a reach that far off can still change course.
  CHECK_FALSE(predict(steady(1.0, 0.3), steady(1.0, 0.3), 0.42));
}

TEST_CASE("degenerate input predicts nothing and never NaN") {
  ContactPredictor predictor;
  CHECK_FALSE(predictor.predicted_contact_us(0));
  // Two samples are too few, a side without a hand forgets its history.
  predictor.add_local({flat_hand(0, 0, 0.10, 0)});
  predictor.add_local({flat_hand(0, 0, 0.09, 10'000)});
  predictor.add_remote({flat_hand(0, 0, 0.10, 0)});
  predictor.add_remote({flat_hand(0, 0, 0.09, 10'000)});
  CHECK_FALSE(predictor.predicted_contact_us(10'000));
  // NaN joints, and samples all at one instant.
  HandSkeleton broken = flat_hand(0, 0, 0.05, 20'000);
  broken.palm.z() = std::numeric_limits<double>::quiet_NaN();
  for (auto& digit : broken.digits) digit[0].z() = std::numeric_limits<double>::quiet_NaN();
  ContactPredictor with_nan;
  for (int i = 0; i < 5; ++i) {
    HandSkeleton hand = broken;
    hand.timestamp_us = uint64_t(i) * 10'000;
    with_nan.add_local({hand});
    with_nan.add_remote({flat_hand(0, 0, 0.05 - 0.005 * i, uint64_t(i) * 10'000)});
  }
  const auto from_the_rest = with_nan.predicted_contact_us(40'000);  // the finite joints still tell
  if (from_the_rest) CHECK(*from_the_rest < 1'000'000);
  ContactPredictor same_instant;
  for (int i = 0; i < 5; ++i) {
    same_instant.add_local({flat_hand(0, 0, 0.05, 7)});
    same_instant.add_remote({flat_hand(0, 0, 0.05, 7)});
  }
  CHECK_FALSE(same_instant.predicted_contact_us(7));
  ContactPredictionParameters bad;
  bad.history_us = 1000;
  CHECK_THROWS_WITH(ContactPredictor(bad), Catch::Contains("history"));
}

namespace {

// The touch loop on a simulated clock: ticks every 20 ms, and a pulse scheduled between ticks
// fired at its time. Both hands follow `path`, seen with no latency.
struct LoopRun {
  std::vector<std::pair<MotorCue, uint64_t>> cues;
  MotorTimingCounts counts;
};
LoopRun run_loop(const Path& path, bool predict, double end_s = 1.2) {
  MotorTiming timing;
  timing.predict = predict;
  LoopRun run;
  TouchLoop loop({}, {}, std::chrono::microseconds(20'000), timing,
                 [&](MotorCue cue, uint64_t now_us, const MotorStep&, Gesture) { run.cues.emplace_back(cue, now_us); });
  for (double t = 0.003; t < end_s; t += 0.02) {
    const double s = std::floor(t / 0.01) * 0.01;  // the tracker's newest frame, every 10 ms
    loop.set_local_hands({flat_hand(0, 0, path(s), us(s))});
    loop.set_remote_hands({flat_hand(0, 0, path(s), us(s))});
    loop.tick(us(t));
    if (auto due = loop.pulse_due_us(); due && *due < us(t + 0.02)) loop.fire_due(*due);
  }
  run.counts = loop.motor_counts();
  return run;
}

}  // namespace

TEST_CASE("with prediction the pulse leaves a spin-up before the contact; without, when the touch is seen") {
  const Path clap = steady(0.60, 0.6);
  const LoopRun predicted = run_loop(clap, true);
  REQUIRE(predicted.cues.size() == 1);
  CHECK(predicted.cues[0].first == MotorCue::Pulse);
  CHECK(std::abs(double(predicted.cues[0].second) - (600'000.0 - 60'000.0)) < 2000.0);
  CHECK(predicted.counts.predicted == 1);
  CHECK(predicted.counts.confirmed == 1);  // the detector saw it: no second pulse
  CHECK(predicted.counts.unpredicted == 0);

  const LoopRun seen = run_loop(clap, false);
  REQUIRE(seen.cues.size() == 1);
  CHECK(seen.cues[0].first == MotorCue::Pulse);
  // The detector takes a touch at 2 cm from the glass: about 33 ms before the contact here.
  CHECK(seen.cues[0].second > 540'000);
  CHECK(seen.counts.unpredicted == 1);
}

TEST_CASE("a predicted contact that does not come is cancelled once, and that reach does not pulse again") {
  // Fast towards the glass, then stopped dead 3 cm short: the prediction fires, the touch never starts.
  const Path stopped = [](double t) { return std::max(0.03, 0.6 * (0.60 - t)); };
  const LoopRun run = run_loop(stopped, true);
  REQUIRE(run.cues.size() == 2);
  CHECK(run.cues[0].first == MotorCue::Pulse);
  CHECK(run.cues[1].first == MotorCue::Cancel);
  CHECK(run.counts.cancelled == 1);
  CHECK(run.counts.confirmed == 0);
}
