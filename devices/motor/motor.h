#pragma once
// The vibration motor on the corner of a screen. One interface, two backends: SimulatedMotor
// (simulated_motor.h) records commands for the demo and the tests; UsbMotor (usb_motor.h)
// drives the Arduino Uno running devices/motor/firmware. Calls block at most for the backend's
// timeouts, so the touch loop calls them from its own thread, never from a render thread.
#include <chrono>
#include <string>
#include <utility>

namespace rt::motor {

// What a command came to: ok, or a sentence that says what is wrong.
class [[nodiscard]] MotorStatus {
 public:
  static MotorStatus success() { return MotorStatus(); }
  static MotorStatus failure(std::string why) { return MotorStatus(std::move(why)); }

  bool ok() const { return error_.empty(); }
  explicit operator bool() const { return ok(); }
  const std::string& error() const { return error_; }

 private:
  MotorStatus() = default;
  explicit MotorStatus(std::string why) : error_(std::move(why)) {
    if (error_.empty()) error_ = "motor command failed for an unknown reason";
  }
  std::string error_;
};

class Motor {
 public:
  virtual ~Motor() = default;

  // Runs the motor for `duration` at PWM duty strength/255, replacing a pulse that is still
  // running. The bounds are the firmware's (firmware/protocol.h): 1..1000 ms and 1..255;
  // a value outside them is rejected with the reason, never clamped.
  virtual MotorStatus pulse(std::chrono::milliseconds duration, int strength) = 0;
  virtual MotorStatus stop() = 0;
};

// Empty when the pulse is inside the protocol's bounds, else what is wrong with it.
std::string check_pulse(std::chrono::milliseconds duration, int strength);

}  // namespace rt::motor
