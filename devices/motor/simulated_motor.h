#pragma once
// A motor without hardware: it checks every command as the firmware would and records the
// accepted ones with a timestamp, so the demo can show when the screen would vibrate and
// tests can check what the touch loop asked for. Thread-safe: the touch loop writes while
// the demo reads.
#include <chrono>
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
  // `spin_up`: from a pulse command to the vibration a hand feels (the link and the motor's
  // inertia); a stop that comes before then cancels the pulse unfelt.
  explicit SimulatedMotor(std::function<uint64_t()> clock = {}, std::chrono::microseconds spin_up = {});

  MotorStatus pulse(std::chrono::milliseconds duration, int strength) override;
  MotorStatus stop() override;

  std::vector<MotorCommand> commands() const;
  // The PWM duty (0..255) the motor would run at, at `time_us`: the last pulse until its
  // deadline, unless a stop came after it.
  int strength_at(uint64_t time_us) const;
  // When each pulse was felt (its command's time plus the spin-up), in order; a pulse cancelled
  // before then, or replaced by a newer command, is not felt.
  std::vector<uint64_t> felt_pulse_starts() const;

 private:
  std::function<uint64_t()> clock_;
  uint64_t spin_up_us_ = 0;
  mutable std::mutex mutex_;
  std::vector<MotorCommand> commands_;
};

}  // namespace rt::motor
