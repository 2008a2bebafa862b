#pragma once
// The phases of a touch, by the distance d of the averaged hand joints to the screen (DESIGN.md
// section 3): the evaluation reports every figure per phase, because the dual model's point is
// what happens as the hand leaves the cameras' view at the glass.
#include <array>
#include <optional>

namespace rt::evaluation {

enum class TouchPhase { Far, Approach, Near, Touching };
inline constexpr int kTouchPhaseCount = 4;
inline constexpr std::array<const char*, kTouchPhaseCount> kTouchPhaseNames = {"far", "approach", "near", "touching"};

inline constexpr double kFarFromM = 0.4;       // far: d >= 0.4 m
inline constexpr double kApproachFromM = 0.2;  // approach: 0.2 <= d < 0.4
inline constexpr double kNearFromM = 0.02;     // near: 0.02 <= d < 0.2; touching: d < 0.02

// Empty for a non-finite distance (no hand).
std::optional<TouchPhase> touch_phase(double distance_m);
inline const char* phase_name(TouchPhase phase) { return kTouchPhaseNames[size_t(phase)]; }

}  // namespace rt::evaluation
