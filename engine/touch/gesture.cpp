#include "touch/gesture.h"

#include <array>

namespace rt {

const char* gesture_name(Gesture gesture) {
  switch (gesture) {
    case Gesture::Palm: return "palm";
    case Gesture::Fist: return "fist";
    case Gesture::Finger: return "finger";
  }
  return "unknown";
}

std::optional<Gesture> gesture_from_name(std::string_view name) {
  for (const Gesture gesture : {Gesture::Palm, Gesture::Fist, Gesture::Finger})
    if (name == gesture_name(gesture)) return gesture;
  return std::nullopt;
}

const std::vector<MotorStep>& motor_pattern(Gesture gesture) {
  using std::chrono::milliseconds;
  // Two knocks far enough apart to feel as two (the motor spins down in about 40 ms).
  static const std::vector<MotorStep> palm{{milliseconds(0), milliseconds(150), 200}},
      fist{{milliseconds(0), milliseconds(60), 255}, {milliseconds(110), milliseconds(60), 255}},
      finger{{milliseconds(0), milliseconds(40), 120}};
  switch (gesture) {
    case Gesture::Fist: return fist;
    case Gesture::Finger: return finger;
    case Gesture::Palm: break;
  }
  return palm;
}

}  // namespace rt
