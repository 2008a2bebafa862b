// `remotetouch bench touch`: the software latency from hands meeting on the glass to the motor
// command, through the real 50 Hz touch loop and a motor backend (simulated: it records when
// each command reaches it). The USB leg, pulse() to the bulk transfer, is measured by the motor
// driver's own test under umockdev (devices/motor/README.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/bench_command.h"
#include "geometry/site_frames.h"
#include "motor/simulated_motor.h"
#include "time/monotonic_clock.h"
#include "touch/touch_loop.h"

namespace rt::app {
namespace {

// An open hand, palm centre at (x, y), every joint `z` from the glass.
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

double percentile(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, size_t(fraction * double(values.size())))];
}

}  // namespace

int run_bench_touch(const RunOptions& options) {
  motor::SimulatedMotor motor(monotonic_now_us);
  TouchLoop loop({}, [&](const TouchEvent& event) {
    if (event.kind == TouchEvent::Kind::Start) (void)motor.pulse(std::chrono::milliseconds(120), 200);
  });
  loop.start();
  std::vector<double> total_ms;
  for (uint32_t trial = 0; trial < options.frames; ++trial) {
    // Apart, until the loop has ended any touch; then both palms on the same spot at t0.
    const size_t before = motor.commands().size();
    for (int i = 0; i < 8; ++i) {
      const uint64_t now = monotonic_now_us();
      loop.set_local_hands({open_hand(0.2, 0.0, 0.3, now)});
      loop.set_remote_hands({});
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    // Vary the phase against the loop's 20 ms period, as real claps do.
    std::this_thread::sleep_for(std::chrono::microseconds(1000 * (trial % 20)));
    const uint64_t t0 = monotonic_now_us();
    loop.set_local_hands({open_hand(0.2, 0.0, 0.005, t0)});
    loop.set_remote_hands({map_skeleton(Site::B, Site::A, open_hand(-0.2, 0.0, 0.005, t0))});
    while (motor.commands().size() == before && monotonic_now_us() - t0 < 1'000'000)
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    const auto commands = motor.commands();
    if (commands.size() == before) throw std::runtime_error("bench touch: no motor command within 1 s of a touch");
    total_ms.push_back(double(commands.back().time_us - t0) / 1000.0);
  }
  loop.stop();
  const double median = percentile(total_ms, 0.5), p90 = percentile(total_ms, 0.9), worst = percentile(total_ms, 1.0);
  double sum = 0.0;
  for (double ms : total_ms) sum += ms;
  const double mean = sum / double(total_ms.size());
  std::printf("touch-start to motor command, %zu claps, 50 Hz touch loop, simulated motor\n", total_ms.size());
  std::printf("  median %.2f ms, 90th percentile %.2f ms, max %.2f ms, mean %.2f ms\n", median, p90, worst, mean);
  nlohmann::json report = {{"claps", total_ms.size()},
                           {"touch_to_motor_ms", {{"median", median}, {"p90", p90}, {"max", worst}, {"mean", mean}}}};
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_touch.json") << report.dump(2) << "\n";
  return 0;
}

std::unique_ptr<Command> make_bench_touch_command() {
  class BenchTouch : public BenchCommand {
   public:
    BenchTouch()
        : BenchCommand("touch",
                       "Software latency from both palms meeting on the glass to the motor command, through the 50 Hz "
                       "touch loop and the simulated motor",
                       "Claps to time") {}
    int run() override { return run_bench_touch(options_); }
  };
  return std::make_unique<BenchTouch>();
}

}  // namespace rt::app
