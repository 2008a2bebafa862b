#include "motor/simulated_motor.h"

#include <algorithm>
#include <chrono>

namespace rt::motor {
namespace {

uint64_t steady_now_us() {
  return uint64_t(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

}  // namespace

SimulatedMotor::SimulatedMotor(std::function<uint64_t()> clock, std::chrono::microseconds spin_up)
    : clock_(clock ? std::move(clock) : std::function<uint64_t()>(steady_now_us)),
      spin_up_us_(uint64_t(std::max<int64_t>(0, spin_up.count()))) {}

MotorStatus SimulatedMotor::pulse(std::chrono::milliseconds duration, int strength) {
  if (std::string why = check_pulse(duration, strength); !why.empty()) return MotorStatus::failure(why);
  MotorCommand command{MotorCommand::Kind::Pulse, clock_(), duration, strength};
  std::lock_guard lock(mutex_);
  commands_.push_back(command);
  return MotorStatus::success();
}

MotorStatus SimulatedMotor::stop() {
  MotorCommand command{MotorCommand::Kind::Stop, clock_(), std::chrono::milliseconds(0), 0};
  std::lock_guard lock(mutex_);
  commands_.push_back(command);
  return MotorStatus::success();
}

std::vector<MotorCommand> SimulatedMotor::commands() const {
  std::lock_guard lock(mutex_);
  return commands_;
}

int SimulatedMotor::strength_at(uint64_t time_us) const {
  std::lock_guard lock(mutex_);
  // The firmware keeps only the newest command, so the last one at or before time_us decides.
  for (auto it = commands_.rbegin(); it != commands_.rend(); ++it) {
    if (it->time_us > time_us) continue;
    if (it->kind == MotorCommand::Kind::Stop) return 0;
    const uint64_t felt_us = it->time_us + spin_up_us_;
    const uint64_t end_us = felt_us + uint64_t(it->duration.count()) * 1000;
    return time_us >= felt_us && time_us < end_us ? it->strength : 0;
  }
  return 0;
}

std::vector<uint64_t> SimulatedMotor::felt_pulse_starts() const {
  std::lock_guard lock(mutex_);
  std::vector<uint64_t> felt;
  for (size_t i = 0; i < commands_.size(); ++i) {
    if (commands_[i].kind != MotorCommand::Kind::Pulse) continue;
    const uint64_t felt_us = commands_[i].time_us + spin_up_us_;
    // The newest command wins: one given before this pulse is felt cancels or replaces it.
    if (i + 1 < commands_.size() && commands_[i + 1].time_us <= felt_us) continue;
    felt.push_back(felt_us);
  }
  return felt;
}

}  // namespace rt::motor
