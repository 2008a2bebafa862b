// The simulated motor: the same bounds as the firmware, and a timestamped record of commands.
#include <catch2/catch.hpp>

#include <thread>

#include "motor/simulated_motor.h"

using namespace std::chrono_literals;
using rt::motor::MotorCommand;
using rt::motor::SimulatedMotor;

TEST_CASE("simulated motor: records accepted commands with their times", "[motor][simulated]") {
  uint64_t now_us = 1'000'000;
  SimulatedMotor motor([&] { return now_us; });
  REQUIRE(motor.pulse(120ms, 200).ok());
  now_us += 50'000;
  REQUIRE(motor.stop().ok());
  now_us += 10'000;
  REQUIRE(motor.pulse(1000ms, 1).ok());

  const auto commands = motor.commands();
  REQUIRE(commands.size() == 3);
  CHECK(commands[0].kind == MotorCommand::Kind::Pulse);
  CHECK(commands[0].time_us == 1'000'000);
  CHECK(commands[0].duration == 120ms);
  CHECK(commands[0].strength == 200);
  CHECK(commands[1].kind == MotorCommand::Kind::Stop);
  CHECK(commands[1].time_us == 1'050'000);
  CHECK(commands[2].time_us == 1'060'000);
  CHECK(commands[2].strength == 1);
}

TEST_CASE("simulated motor: rejects what the firmware rejects, records nothing", "[motor][simulated]") {
  SimulatedMotor motor([] { return uint64_t(0); });
  const auto too_short = motor.pulse(0ms, 100);
  CHECK_FALSE(too_short.ok());
  CHECK(too_short.error() == "pulse duration 0 ms is out of range 1..1000 ms (hold the motor on by repeating pulses)");
  CHECK_FALSE(motor.pulse(1001ms, 100).ok());
  CHECK_FALSE(motor.pulse(-5ms, 100).ok());
  const auto too_weak = motor.pulse(100ms, 0);
  CHECK(too_weak.error() == "pulse strength 0 is out of range 1..255 (PWM duty in 1/255; use stop() for 0)");
  CHECK_FALSE(motor.pulse(100ms, 256).ok());
  CHECK_FALSE(motor.pulse(100ms, -1).ok());
  CHECK(motor.commands().empty());
}

TEST_CASE("simulated motor: strength over time follows the newest command", "[motor][simulated]") {
  uint64_t now_us = 0;
  SimulatedMotor motor([&] { return now_us; });
  CHECK(motor.strength_at(0) == 0);
  now_us = 1000;
  REQUIRE(motor.pulse(100ms, 180).ok());
  CHECK(motor.strength_at(999) == 0);
  CHECK(motor.strength_at(1000) == 180);
  CHECK(motor.strength_at(100'999) == 180);
  CHECK(motor.strength_at(101'000) == 0);  // the pulse's deadline stops it
  now_us = 50'000;
  REQUIRE(motor.pulse(10ms, 90).ok());  // a new pulse replaces the running one
  CHECK(motor.strength_at(55'000) == 90);
  CHECK(motor.strength_at(60'000) == 0);
  now_us = 58'000;
  REQUIRE(motor.stop().ok());
  CHECK(motor.strength_at(58'000) == 0);
}

TEST_CASE("simulated motor: default clock is monotonic and the record is thread-safe", "[motor][simulated]") {
  SimulatedMotor motor;
  std::thread writer([&] {
    for (int i = 0; i < 500; ++i) REQUIRE(motor.pulse(10ms, 1 + i % 255).ok());
  });
  for (int i = 0; i < 100; ++i) (void)motor.commands();
  writer.join();
  const auto commands = motor.commands();
  REQUIRE(commands.size() == 500);
  for (size_t i = 1; i < commands.size(); ++i) CHECK(commands[i].time_us >= commands[i - 1].time_us);
  CHECK(commands.back().time_us > 0);
}

TEST_CASE("simulated motor: a pulse is felt after the spin-up, and a stop before then cancels it", "[motor][simulated]") {
  uint64_t now_us = 10'000;
  SimulatedMotor motor([&] { return now_us; }, 60ms);
  REQUIRE(motor.pulse(100ms, 200).ok());
  CHECK(motor.strength_at(69'999) == 0);
  CHECK(motor.strength_at(70'000) == 200);
  CHECK(motor.strength_at(169'999) == 200);
  CHECK(motor.strength_at(170'000) == 0);
  now_us = 300'000;
  REQUIRE(motor.pulse(100ms, 150).ok());
  now_us = 359'000;  // before the second pulse is felt: it never is
  REQUIRE(motor.stop().ok());
  CHECK(motor.strength_at(365'000) == 0);
  CHECK(motor.felt_pulse_starts() == std::vector<uint64_t>{70'000});
}
