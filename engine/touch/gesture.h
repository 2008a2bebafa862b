#pragma once
// What kind of touch the two hands make on the glass, and how the motor says so: a clap or a
// high five (palm), a fist bump (fist), a fingertip touch (finger), each with a vibration of its
// own so that a user feels which touch the other side made.
#include <chrono>
#include <optional>
#include <string_view>
#include <vector>

namespace rt {

enum class Gesture { Palm, Fist, Finger };

const char* gesture_name(Gesture gesture);  // "palm", "fist", "finger"
std::optional<Gesture> gesture_from_name(std::string_view name);

// One run of the motor, `after` the pattern's start.
struct MotorStep {
  std::chrono::milliseconds after{0};
  std::chrono::milliseconds duration{0};
  int strength = 0;  // PWM duty, 1..255
};

// Palm: one 150 ms pulse (as the paper's motor gives every touch); fist: a shorter, stronger
// double knock; finger: a short light tick. The first step starts at 0.
const std::vector<MotorStep>& motor_pattern(Gesture gesture);

}  // namespace rt
