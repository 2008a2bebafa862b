#include "motor/motor.h"

#include "motor/firmware/protocol.h"

namespace rt::motor {

std::string check_pulse(std::chrono::milliseconds duration, int strength) {
  const long long ms = duration.count();
  if (ms < MOTOR_DURATION_MIN_MS || ms > MOTOR_DURATION_MAX_MS) {
    return "pulse duration " + std::to_string(ms) + " ms is out of range " + std::to_string(MOTOR_DURATION_MIN_MS) +
           ".." + std::to_string(MOTOR_DURATION_MAX_MS) + " ms (hold the motor on by repeating pulses)";
  }
  if (strength < int(MOTOR_STRENGTH_MIN) || strength > int(MOTOR_STRENGTH_MAX)) {
    return "pulse strength " + std::to_string(strength) + " is out of range " + std::to_string(MOTOR_STRENGTH_MIN) +
           ".." + std::to_string(MOTOR_STRENGTH_MAX) + " (PWM duty in 1/255; use stop() for 0)";
  }
  return {};
}

}  // namespace rt::motor
