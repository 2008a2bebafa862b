#pragma once
// A motor without hardware: it checks every command as the firmware would and records the
// accepted ones with a timestamp, so the demo can show when the screen would vibrate and
// tests can check what the touch loop asked for. Thread-safe: the touch loop writes while
// the demo reads.
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "motor/motor.h"

namespace rt::motor {

struct MotorCommand {
  enum class Kind { Pulse, Stop };
  Kind kind = Kind::Stop;
  uint64_t time_us = 0;  // when the command was given, microseconds of the monotonic clock
  std::chrono::milliseconds duration{0};  // pulses only
  int strength = 0;                       // pulses only
};

class SimulatedMotor final : public Motor {
 public:
  // `clock` returns microseconds of a monotonic clock; the default is std::chrono::steady_clock,
  // the clock every RemoteTouch timestamp uses (DESIGN.md section 2).
  explicit SimulatedMotor(std::function<uint64_t()> clock = {});

  MotorStatus pulse(std::chrono::milliseconds duration, int strength) override;
  MotorStatus stop() override;

  std::vector<MotorCommand> commands() const;
  // The PWM duty (0..255) the motor would run at, at `time_us`: the last pulse until its
  // deadline, unless a stop came after it.
  int strength_at(uint64_t time_us) const;

 private:
  std::function<uint64_t()> clock_;
  mutable std::mutex mutex_;
  std::vector<MotorCommand> commands_;
};

}  // namespace rt::motor
