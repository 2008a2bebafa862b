#include "evaluation/touch_phase.h"

#include <cmath>

namespace rt::evaluation {

std::optional<TouchPhase> touch_phase(double distance_m) {
  if (!std::isfinite(distance_m)) return std::nullopt;
  if (distance_m >= kFarFromM) return TouchPhase::Far;
  if (distance_m >= kApproachFromM) return TouchPhase::Approach;
  if (distance_m >= kNearFromM) return TouchPhase::Near;
  return TouchPhase::Touching;
}

}  // namespace rt::evaluation
