#pragma once
// Scripted motions of the simulated user: keyframed body poses (torso lean, each hand's palm
// position, orientation and finger curl), eased with smoothstep between keyframes so that every
// joint starts and stops smoothly and never overshoots a keyframe: the palm approaches the
// glass along a straight line and stops on it, so no joint passes through the screen.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/person.h"
#include "sim/person_pose.h"
#include "sim/site_description.h"

namespace rt::sim {

enum class MotionKind {
  Idle,          // seated, hands on the thighs, breathing
  Raise,         // raise the right hand in front of the shoulder
  Approach,      // from raised to just in front of the touch spot
  TouchHold,     // press the palm flat on the glass and hold it there
  Retract,       // from the glass back to rest
  Wave,          // wave in front of the chest: the hand hides the body from the cameras
  FastApproach,  // from rest straight to the glass, quickly
  Clap,          // raise, approach, touch_hold, retract
  FistBump,      // a clap with a closed fist, knuckles forward onto the glass
  FingerTouch,   // a clap with a pointing hand: the index fingertip onto the glass
  Graze,         // a clap whose palm slides down the glass while it is on it
};
const std::vector<MotionKind>& all_motion_kinds();
const char* motion_name(MotionKind kind);
std::optional<MotionKind> motion_kind_from_name(std::string_view name);

struct MotionSpec {
  MotionKind kind = MotionKind::Idle;
  // Where the palm centre touches the glass, (x, y) in this site's frame. The same spot on the
  // shared glass is (x, y) at site A and (-x, y) at site B.
  Eigen::Vector2d touch_target_m = Eigen::Vector2d(0.08, 0.05);
  double start_delay_s = 0.0;  // the first pose is held this long
  double hold_s = 1.0;         // time the palm stays on the glass (touch_hold, fast_approach, clap, ...)
  double speed = 1.0;          // > 1 plays the moves faster (not the hold)
  // > 0: the motion starts again from its first pose this often, seconds (a long soak run of a
  // short scene); at least the motion's own length. 0: it plays once and holds its last pose.
  double repeat_every_s = 0.0;
};

// JSON: {"name": "clap", "touch_target_m": [x, y], "start_delay_s", "hold_s", "speed",
// "repeat_every_s"}; all but
// the name are optional. Errors start with `where`.
MotionSpec motion_from_json(const nlohmann::json& json, const std::string& where);
nlohmann::json motion_to_json(const MotionSpec& spec);

// The palm's joints at the touch sit this far in front of the glass (the skeleton runs through
// the middle of the hand, about half a centimetre above the skin of a flat palm).
inline constexpr double kTouchPalmHeightM = 0.005;
// A fist bump's nearest joints (the knuckles between the first and second finger bones) sit this
// far in front of the glass: less than a finger's half thickness, as a bump presses the knuckles'
// skin flat on it.
inline constexpr double kFistKnuckleHeightM = 0.005;
// A fingertip touch's index tip joint sits this far in front of the glass: the pad pressed flat.
inline constexpr double kFingertipHeightM = 0.004;
// How far a graze's palm slides down the glass while on it.
inline constexpr double kGrazeSlideM = 0.12;

// A motion's keyframes, built once for a user in a seat. Throws std::invalid_argument when the
// touch target cannot be reached from the seat.
class MotionTrack {
 public:
  MotionTrack(const MotionSpec& spec, const Seat& seat, const UserAppearance& appearance);

  PersonPose pose_at(double t_s) const;
  // When the last keyframe is reached; the pose holds after it (and before 0), unless the spec
  // repeats the motion.
  double duration_s() const { return keys_.back().t_s; }
  const BodyGeometry& body() const { return body_; }
  const MotionSpec& spec() const { return spec_; }

 private:
  struct Keyframe {
    double t_s = 0.0;
    BodyKey body;
  };
  void add(double after_s, const BodyKey& body);

  MotionSpec spec_;
  BodyGeometry body_;
  std::vector<Keyframe> keys_;
};

// Builds the track on every call: for a single pose. Use MotionTrack to sample many.
PersonPose evaluate_motion(const MotionSpec& spec, const Seat& seat, const UserAppearance& appearance, double t_s);

}  // namespace rt::sim
