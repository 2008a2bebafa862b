// `remotetouch bench touch`: from the moment the palms meet on the glass to the moment the motor
// vibrates, over many claps of varied speed, without and with contact prediction
// (touch/touch_loop.h). The claps run on a simulated clock through the real touch loop's ticks
// and the simulated motor with its spin-up, so the truth (when the palms meet) is exact and the
// run takes no wall time. Misses, grazes and hovers, which must not vibrate, run beside them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "app/bench_command.h"
#include "geometry/site_frames.h"
#include "motor/simulated_motor.h"
#include "touch/touch_loop.h"

namespace rt::app {
namespace {

// An open hand flat to the glass, palm centre at (x, y), every joint `z` from it.
HandSkeleton open_hand(double x, double y, double z, uint64_t timestamp_us) {
  HandSkeleton hand;
  hand.timestamp_us = timestamp_us;
  hand.palm = {x, y, z};
  hand.wrist = {x, y - 0.06, z};
  const double spread[kDigitCount] = {-0.045, -0.025, -0.005, 0.015, 0.035};
  for (int d = 0; d < kDigitCount; ++d)
    for (int j = 0; j < kJointsPerDigit; ++j) hand.digits[d][j] = {x + spread[d], y + 0.02 * j, z};
  return hand;
}

// One hand's reach: a minimum-jerk movement (how people reach) from 30 cm out towards a point
// `through_m` behind the glass, taking `reach_s`; the glass stops it where it crosses, and it
// holds there, then leaves. A point just behind the glass gives a soft arrival, a far one a
// fast clap. `stop_m` > 0 aims in front of the glass instead, where the hand stops (a hover).
struct Reach {
  double start_s = 0, reach_s = 0.5, through_m = 0.05, stop_m = 0.0, x = 0.0;
  static constexpr double kStart = 0.30, kHold = 0.4;
  double free_z(double s) const {
    const double u = std::clamp(s / reach_s, 0.0, 1.0);
    const double target = stop_m > 0 ? stop_m : -through_m;
    return kStart + (target - kStart) * (u * u * u * (10 - 15 * u + 6 * u * u));
  }
  double contact_s() const {
    if (stop_m > 0) return start_s + reach_s;
    double lo = 0, hi = reach_s;  // free_z falls monotonically through 0: bisect
    for (int i = 0; i < 60; ++i) (free_z(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
    return start_s + hi;
  }
  double z(double t) const {
    const double s = t - start_s, arrive = contact_s() - start_s;
    if (s <= arrive) return std::max(free_z(s), stop_m);
    if (s <= arrive + kHold) return stop_m;
    return stop_m + 0.5 * (s - arrive - kHold);
  }
};

enum class Kind { Clap, Miss, Graze, Hover };

struct Trial {
  Kind kind = Kind::Clap;
  Reach local, remote;  // the remote hand in the local site frame
  double network_jitter_s = 0;
  double clock_bias_s = 0;  // the error of the other site's clock mapped to this one
};

struct Latencies {
  double tracker_s = 0.020;      // capture to the skeleton in the touch loop
  double network_s = 0.030;      // the remote skeleton's one-way trip, as the site estimates it
  double network_jitter_s = 0.010;
  double tracker_hz = 90;
  double noise_m = 0.001;        // tracker noise on each coordinate of each joint
  double clock_bias_s = 0.003;   // at most this error in mapping the other site's clock
};

struct TrialResult {
  std::vector<uint64_t> felt_us;
  uint64_t contact_us = 0;
  MotorTimingCounts counts;
};

// One trial on the simulated clock: the tracker's samples arrive late, the touch loop ticks at
// 50 Hz from a random phase and wakes for a pulse scheduled between ticks.
TrialResult run_trial(const Trial& trial, const Latencies& latency, bool predict, std::mt19937& random) {
  uint64_t now_us = 0;
  motor::SimulatedMotor motor([&] { return now_us; }, std::chrono::microseconds(60'000));
  MotorTiming timing;
  timing.predict = predict;
  timing.motor_spin_up_us = 60'000;
  // The site's own touch parameters (site_run.cpp): a skeleton counts as lost after 200 ms, as
  // the remote one arrives a link's delay after its capture.
  TouchParameters touch;
  touch.max_skeleton_age_us = 200'000;
  touch.touch_hold_age_us = 1'000'000;
  TouchLoop loop(touch, {}, std::chrono::microseconds(20'000), timing, [&](MotorCue cue, uint64_t, const MotorStep&, Gesture) {
    if (cue == MotorCue::Pulse)
      (void)motor.pulse(std::chrono::milliseconds(150), 200);
    else
      (void)motor.stop();
  });
  std::normal_distribution<double> noise(0.0, latency.noise_m);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // The simulator's tracker jitter: independent noise on every joint (sim/effects.h); nothing
  // reported behind the glass.
  auto sample = [&](const Reach& reach, double t, uint64_t stamp_us) {
    HandSkeleton hand = open_hand(reach.x, 0.0, reach.z(t), stamp_us);
    auto jitter = [&](Eigen::Vector3d& joint) {
      joint += Eigen::Vector3d(noise(random), noise(random), noise(random));
      joint.z() = std::max(0.0, joint.z());
    };
    jitter(hand.palm);
    jitter(hand.wrist);
    for (auto& digit : hand.digits)
      for (auto& joint : digit) jitter(joint);
    return hand;
  };
  const double end_s = std::max(trial.local.contact_s(), trial.remote.contact_s()) + 0.8;
  const double frame_s = 1.0 / latency.tracker_hz;
  double next_capture_s = unit(random) * frame_s;
  double next_tick_s = unit(random) * 0.020;
  // Samples in flight: (arrival, skeleton) for each side.
  std::vector<std::pair<double, HandSkeleton>> local_in_flight, remote_in_flight;
  while (next_tick_s < end_s) {
    while (next_capture_s <= next_tick_s) {
      const uint64_t capture_us = uint64_t(next_capture_s * 1e6);
      local_in_flight.emplace_back(next_capture_s + latency.tracker_s, sample(trial.local, next_capture_s, capture_us));
      // The remote skeleton carries its capture time in the other site's clock, which the site
      // maps to its own through the clocks' offset; what the offset's estimate gets wrong (the
      // link's asymmetry) shifts every remote stamp alike. The jitter delays arrivals only.
      const double arrival = next_capture_s + latency.tracker_s + latency.network_s + trial.network_jitter_s * unit(random);
      remote_in_flight.emplace_back(arrival, sample(trial.remote, next_capture_s,
                                                    uint64_t(std::max(0.0, next_capture_s + trial.clock_bias_s) * 1e6)));
      next_capture_s += frame_s;
    }
    auto newest_arrived = [&](std::vector<std::pair<double, HandSkeleton>>& in_flight) {
      std::optional<HandSkeleton> newest;
      for (const auto& [arrival, hand] : in_flight)
        if (arrival <= next_tick_s && (!newest || hand.timestamp_us > newest->timestamp_us)) newest = hand;
      return newest;
    };
    if (auto hand = newest_arrived(local_in_flight)) loop.set_local_hands({*hand});
    if (auto hand = newest_arrived(remote_in_flight)) loop.set_remote_hands({*hand});
    now_us = uint64_t(next_tick_s * 1e6);
    loop.tick(now_us);
    const uint64_t next_tick_us = uint64_t((next_tick_s + 0.020) * 1e6);
    if (const std::optional<uint64_t> due = loop.pulse_due_us(); due && *due < next_tick_us) {
      now_us = *due;
      loop.fire_due(now_us);
    }
    next_tick_s += 0.020;
  }
  TrialResult result;
  result.felt_us = motor.felt_pulse_starts();
  result.contact_us = uint64_t(std::max(trial.local.contact_s(), trial.remote.contact_s()) * 1e6);
  result.counts = loop.motor_counts();
  return result;
}

std::vector<Trial> make_trials(uint32_t claps, const Latencies& latency, std::mt19937& random) {
  std::uniform_real_distribution<double> reach_s(0.3, 0.8), through(0.01, 0.15), offset(-0.04, 0.04), jitter(0, 1),
      bias(-latency.clock_bias_s, latency.clock_bias_s);
  auto reach = [&](double x) { return Reach{0.2, reach_s(random), through(random), 0.0, x}; };
  std::vector<Trial> trials;
  for (uint32_t i = 0; i < claps; ++i) {
    Trial trial{Kind::Clap, reach(0.0), reach(0.0), latency.network_jitter_s * jitter(random), bias(random)};
    // The two users rarely arrive together: the later palm decides the contact.
    trial.remote.start_s += trial.local.contact_s() + offset(random) - trial.remote.contact_s();
    trials.push_back(trial);
  }
  // Ten of each that must not vibrate: palms far apart (miss), palms passing 3 cm apart on the
  // glass (graze), both hands slowing to a stop 3 cm short of it (hover).
  for (int i = 0; i < 10; ++i) {
    trials.push_back({Kind::Miss, reach(-0.15), reach(0.15), 0});
    trials.push_back({Kind::Graze, reach(0.0), reach(0.11), 0});
    Trial hover{Kind::Hover, reach(0.0), reach(0.0), 0};
    hover.local.stop_m = hover.remote.stop_m = 0.03;
    trials.push_back(hover);
  }
  return trials;
}

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, size_t(fraction * double(values.size())))];
}

nlohmann::json run_mode(const std::vector<Trial>& trials, const Latencies& latency, bool predict, uint32_t seed) {
  std::mt19937 random(seed);
  std::vector<double> errors_ms, abs_errors_ms;
  uint64_t false_pulses = 0, missed = 0;
  MotorTimingCounts counts;
  for (const Trial& trial : trials) {
    const TrialResult result = run_trial(trial, latency, predict, random);
    counts.predicted += result.counts.predicted;
    counts.confirmed += result.counts.confirmed;
    counts.cancelled += result.counts.cancelled;
    counts.unpredicted += result.counts.unpredicted;
    if (trial.kind != Kind::Clap) {
      false_pulses += result.felt_us.size();
      continue;
    }
    if (result.felt_us.empty()) {
      ++missed;
      continue;
    }
    const double error_ms = (double(result.felt_us.front()) - double(result.contact_us)) / 1000.0;
    errors_ms.push_back(error_ms);
    abs_errors_ms.push_back(std::abs(error_ms));
    false_pulses += result.felt_us.size() - 1;
  }
  return {{"claps_felt", errors_ms.size()},
          {"claps_not_felt", missed},
          {"contact_to_vibration_ms",
           {{"median", percentile(errors_ms, 0.5)}, {"abs_p90", percentile(abs_errors_ms, 0.9)},
            {"abs_max", percentile(abs_errors_ms, 1.0)}, {"min", percentile(errors_ms, 0.0)}}},
          {"false_pulses", false_pulses},
          {"pulses", {{"predicted", counts.predicted}, {"confirmed", counts.confirmed}, {"cancelled", counts.cancelled},
                      {"unpredicted", counts.unpredicted}}}};
}

}  // namespace

int run_bench_touch(const RunOptions& options) {
  const Latencies latency;
  std::mt19937 random(7);
  const std::vector<Trial> trials = make_trials(options.frames, latency, random);
  nlohmann::json report = {{"claps", options.frames},
                           {"motor_spin_up_ms", 60},
                           {"tracker_latency_ms", latency.tracker_s * 1e3},
                           {"network_latency_ms", latency.network_s * 1e3},
                           {"network_jitter_ms", latency.network_jitter_s * 1e3},
                           {"tracker_hz", latency.tracker_hz}};
  std::printf("contact to vibration, %u claps of varied speed (minimum-jerk reaches of 0.3-0.8 s aimed 1-15 cm through the glass),\n"
              "motor spin-up 60 ms, tracker %.0f Hz + %.0f ms, network %.0f ms + up to %.0f ms jitter; "
              "10 misses, 10 grazes, 10 hovers\n",
              options.frames, latency.tracker_hz, latency.tracker_s * 1e3, latency.network_s * 1e3,
              latency.network_jitter_s * 1e3);
  for (const bool predict : {false, true}) {
    const nlohmann::json mode = run_mode(trials, latency, predict, 11);
    const nlohmann::json& e = mode["contact_to_vibration_ms"];
    std::printf("  %-18s median %+.1f ms, |error| 90th percentile %.1f ms, max %.1f ms; %d of %u felt; "
                "%d false pulses; pulses predicted %d (cancelled %d), unpredicted %d\n",
                predict ? "with prediction" : "without prediction", e["median"].get<double>(), e["abs_p90"].get<double>(),
                e["abs_max"].get<double>(), mode["claps_felt"].get<int>(), options.frames, mode["false_pulses"].get<int>(),
                mode["pulses"]["predicted"].get<int>(), mode["pulses"]["cancelled"].get<int>(),
                mode["pulses"]["unpredicted"].get<int>());
    report[predict ? "with_prediction" : "without_prediction"] = mode;
  }
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_touch.json") << report.dump(2) << "\n";
  return 0;
}

std::unique_ptr<Command> make_bench_touch_command() {
  class BenchTouch : public BenchCommand {
   public:
    BenchTouch()
        : BenchCommand("touch",
                       "From the palms meeting on the glass to the motor's vibration, over claps of varied speed, "
                       "without and with contact prediction (a simulated clock: no wall time)",
                       "Claps to time") {}
    int run() override { return run_bench_touch(options_); }

   protected:
    void add_options(CLI::App& command) override {
      options_.frames = 60;
      command.get_option("--frames")->default_str("60");
    }
  };
  return std::make_unique<BenchTouch>();
}

}  // namespace rt::app

