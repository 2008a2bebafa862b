#include "sim/motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "config/json.h"

namespace rt::sim {

using namespace config;  // the JSON readers

namespace {

struct NamedKind {
  MotionKind kind;
  const char* name;
};
constexpr NamedKind kMotionNames[] = {
    {MotionKind::Idle, "idle"},         {MotionKind::Raise, "raise"},
    {MotionKind::Approach, "approach"}, {MotionKind::TouchHold, "touch_hold"},
    {MotionKind::Retract, "retract"},   {MotionKind::Wave, "wave"},
    {MotionKind::FastApproach, "fast_approach"}, {MotionKind::Clap, "clap"},
    {MotionKind::FistBump, "fist_bump"},         {MotionKind::FingerTouch, "finger_touch"},
    {MotionKind::Graze, "graze"},
};

// Breathing: a slow, small forward sway of the torso, always on, so no user is a statue.
constexpr double kBreathPeriodS = 4.0;
constexpr double kBreathLeanRad = 0.012;

// Durations of the moves at speed 1, seconds.
constexpr double kRaiseS = 1.0;
constexpr double kApproachS = 1.0;
constexpr double kPressS = 0.35;  // from just in front of the glass onto it
constexpr double kLiftS = 0.3;
constexpr double kLowerToRaisedS = 0.7;
constexpr double kLowerToRestS = 0.9;
constexpr double kFastReachS = 0.6;
constexpr double kFastPressS = 0.15;
constexpr double kWaveStrokeS = 0.3;
constexpr int kWaveStrokes = 6;
constexpr double kIdleS = 4.0;

constexpr double kPreTouchHeightM = 0.06;  // hand flat and aimed, just before the press
constexpr double kLiftHeightM = 0.08;

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

HandPlacement blend(const HandPlacement& a, const HandPlacement& b, double s) {
  HandPlacement hand;
  hand.palm = a.palm + s * (b.palm - a.palm);
  hand.orientation = a.orientation.slerp(s, b.orientation);
  hand.curl = a.curl + s * (b.curl - a.curl);
  for (size_t d = 0; d < hand.extra_curl.size(); ++d)
    hand.extra_curl[d] = a.extra_curl[d] + s * (b.extra_curl[d] - a.extra_curl[d]);
  return hand;
}

BodyKey blend(const BodyKey& a, const BodyKey& b, double s) {
  return {a.lean_rad + s * (b.lean_rad - a.lean_rad), blend(a.right, b.right, s), blend(a.left, b.left, s)};
}

Eigen::Quaterniond palm_towards_screen() { return hand_orientation(Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ()); }

// What the hand does at the glass: a flat palm, a closed fist with its knuckles forward, or a
// pointing index finger.
enum class HandShape { Open, Fist, Point };

HandShape shape_of(MotionKind kind) {
  if (kind == MotionKind::FistBump) return HandShape::Fist;
  if (kind == MotionKind::FingerTouch) return HandShape::Point;
  return HandShape::Open;
}

// A fist bump's hand: the backs of the first finger bones face the glass. At full curl they
// turn `knuckle` from the hand's direction towards the palm, so the hand's direction leans that
// much from the screen's normal, palm down.
Eigen::Quaterniond fist_towards_screen() {
  const double knuckle = medium_adult_hand()[int(Digit::Middle)].max_flexion_deg[0] * std::numbers::pi / 180.0;
  const Eigen::Vector3d towards_screen = -Eigen::Vector3d::UnitZ(), down = -Eigen::Vector3d::UnitY();
  return hand_orientation(std::sin(knuckle) * towards_screen + std::cos(knuckle) * down,
                          -std::cos(knuckle) * towards_screen + std::sin(knuckle) * down);
}

// A pointing hand: the index finger 50 degrees from the screen's normal, up, so that the pad of
// its tip, not its nail or its very end, meets the glass; the palm faces down and forward.
Eigen::Quaterniond point_towards_screen() {
  constexpr double kFromNormal = 50.0 * std::numbers::pi / 180.0;
  const Eigen::Vector3d towards_screen = -Eigen::Vector3d::UnitZ(), up = Eigen::Vector3d::UnitY();
  return hand_orientation(std::cos(kFromNormal) * towards_screen + std::sin(kFromNormal) * up,
                          std::sin(kFromNormal) * towards_screen - std::cos(kFromNormal) * up);
}

// The key poses a motion moves between; `target` is the touch spot on the glass.
class KeyPoses {
 public:
  KeyPoses(const BodyGeometry& body, const Eigen::Vector2d& target, HandShape shape = HandShape::Open)
      : body_(body), target_(target), shape_(shape) {}

  BodyKey rest() const { return {0.0, resting_hand(body_, true), resting_hand(body_, false)}; }

  BodyKey raised() const {
    BodyKey key = rest();
    key.lean_rad = 0.06;
    // Beyond d_max, where the cameras see the hand well and appearance adaption fits it.
    key.right.palm = {target_.x() + 0.04, target_.y() - 0.06, body_.head_rest.z() - 0.24};
    key.right.orientation = palm_towards_screen();
    key.right.curl = 0.3;
    if (shape_ != HandShape::Open) shape_hand(key.right);
    return key;
  }

  // The hand aimed at the target with its part that touches (the palm, the fist's knuckles, the
  // index tip) at `height` above it; the torso leans in as far as the arm needs (and at least as
  // far as when raised, so the lean never goes back and forth).
  BodyKey over_target(double height_m, double curl) const {
    BodyKey key = raised();
    key.right.palm = {target_.x(), target_.y(), height_m};
    key.right.curl = curl;
    if (shape_ != HandShape::Open) {
      shape_hand(key.right);
      // Placed by its nearest joints: the fist's knuckles, the index tip.
      key.right.palm = Eigen::Vector3d::Zero();
      const HandSkeleton at_origin = build_hand(key.right, false, body_.hand_scale);
      const Eigen::Vector3d touching = touching_point(at_origin);
      key.right.palm = Eigen::Vector3d(target_.x(), target_.y(), height_m) - touching;
    }
    const HandSkeleton hand = build_hand(key.right, false, body_.hand_scale);
    const std::optional<double> lean = lean_to_reach(body_, hand.wrist, true);
    if (!lean) {
      std::ostringstream message;
      message << "touch target (" << target_.x() << ", " << target_.y() << ") is out of reach of the user's right arm "
              << "from the seat, even leaning in " << kMaxLeanRad << " rad; choose a spot closer to the right shoulder";
      throw std::invalid_argument(message.str());
    }
    key.lean_rad = std::max(key.lean_rad, *lean);
    return key;
  }
  BodyKey pre_touch() const { return over_target(kPreTouchHeightM, 0.05); }
  BodyKey touch() const {
    BodyKey key = over_target(touch_height_m(), 0.0);
    key.lean_rad = std::max(key.lean_rad, pre_touch().lean_rad);
    return key;
  }
  BodyKey lifted() const {
    if (shape_ != HandShape::Open) {
      BodyKey key = over_target(kLiftHeightM, 0.0);
      key.lean_rad = std::max(key.lean_rad, touch().lean_rad);
      return key;
    }
    BodyKey key = touch();
    key.right.palm.z() = kLiftHeightM;
    key.right.curl = 0.1;
    return key;
  }

  // In front of the chest, palm to the cameras; `stroke` -1/+1 swings the hand to one side.
  BodyKey wave(int stroke) const {
    BodyKey key = rest();
    key.lean_rad = 0.03;
    key.right.palm = body_.head_rest + Eigen::Vector3d(0.05 + 0.08 * stroke, -0.25, -0.28);
    key.right.orientation =
        Eigen::AngleAxisd(-0.35 * stroke, Eigen::Vector3d::UnitZ()) * palm_towards_screen();
    key.right.curl = 0.1;
    return key;
  }

 private:
  // The fist and the pointing hand keep their shape from the raise to the retract.
  void shape_hand(HandPlacement& hand) const {
    hand.curl = 1.0;
    hand.extra_curl = {};
    if (shape_ == HandShape::Fist) {
      hand.orientation = fist_towards_screen();
    } else {
      hand.orientation = point_towards_screen();
      hand.extra_curl[int(Digit::Index)] = -1.0;
      hand.extra_curl[int(Digit::Thumb)] = -0.4;  // laid along the curled middle finger
    }
  }
  double touch_height_m() const {
    if (shape_ == HandShape::Fist) return kFistKnuckleHeightM;
    if (shape_ == HandShape::Point) return kFingertipHeightM;
    return kTouchPalmHeightM;
  }
  // Where the shaped hand meets the glass: x and y of its touching part, z of its nearest joint.
  Eigen::Vector3d touching_point(const HandSkeleton& hand) const {
    if (shape_ == HandShape::Point) return hand.joint(Digit::Index, DigitJoint::Tip);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double nearest_z = 1e9;
    for (Digit digit : {Digit::Index, Digit::Middle, Digit::Ring, Digit::Pinky})
      for (DigitJoint joint : {DigitJoint::Mcp, DigitJoint::Pip}) sum += hand.joint(digit, joint);
    for (const Eigen::Vector3d& joint : hand.hand_joints()) nearest_z = std::min(nearest_z, joint.z());
    return {sum.x() / 8, sum.y() / 8, nearest_z};
  }

  const BodyGeometry& body_;
  Eigen::Vector2d target_;
  HandShape shape_;
};

std::string known_motion_names() {
  std::string list;
  for (const NamedKind& entry : kMotionNames) list += std::string(list.empty() ? "" : ", ") + entry.name;
  return list;
}

}  // namespace

const std::vector<MotionKind>& all_motion_kinds() {
  static const std::vector<MotionKind> kinds = [] {
    std::vector<MotionKind> all;
    for (const NamedKind& entry : kMotionNames) all.push_back(entry.kind);
    return all;
  }();
  return kinds;
}

const char* motion_name(MotionKind kind) {
  for (const NamedKind& entry : kMotionNames)
    if (entry.kind == kind) return entry.name;
  return "unknown";
}

std::optional<MotionKind> motion_kind_from_name(std::string_view name) {
  for (const NamedKind& entry : kMotionNames)
    if (name == entry.name) return entry.kind;
  return std::nullopt;
}

MotionSpec motion_from_json(const nlohmann::json& json, const std::string& where) {
  reject_unknown_fields(json, {"name", "touch_target_m", "start_delay_s", "hold_s", "speed", "repeat_every_s"}, where);
  MotionSpec spec;
  const std::string name = config::require_string(json, "name", where);
  const std::optional<MotionKind> kind = motion_kind_from_name(name);
  if (!kind) throw config::JsonError(where + ": field 'name': unknown motion '" + name + "' (known: " + known_motion_names() + ")");
  spec.kind = *kind;
  if (json.contains("touch_target_m")) spec.touch_target_m = require_vec2(json, "touch_target_m", where);
  if (json.contains("start_delay_s")) spec.start_delay_s = require_in_range(json, "start_delay_s", where, 0.0, 3600.0);
  if (json.contains("hold_s")) spec.hold_s = require_in_range(json, "hold_s", where, 0.0, 3600.0);
  if (json.contains("speed")) spec.speed = require_in_range(json, "speed", where, 0.25, 4.0);
  if (json.contains("repeat_every_s")) spec.repeat_every_s = require_in_range(json, "repeat_every_s", where, 0.0, 3600.0);
  return spec;
}

nlohmann::json motion_to_json(const MotionSpec& spec) {
  return {{"name", motion_name(spec.kind)},
          {"touch_target_m", to_json(spec.touch_target_m)},
          {"start_delay_s", spec.start_delay_s},
          {"hold_s", spec.hold_s},
          {"speed", spec.speed},
          {"repeat_every_s", spec.repeat_every_s}};
}

void MotionTrack::add(double after_s, const BodyKey& body) {
  // `after_s` is the time since the previous keyframe; the first keyframe waits for the start delay.
  keys_.push_back({keys_.empty() ? spec_.start_delay_s : keys_.back().t_s + after_s, body});
}

MotionTrack::MotionTrack(const MotionSpec& spec, const Seat& seat, const UserAppearance& appearance)
    : spec_(spec), body_(body_for(seat, appearance)) {
  if (!(spec.speed > 0) || !std::isfinite(spec.speed)) throw std::invalid_argument("motion speed must be > 0");
  if (!(spec.hold_s >= 0) || !(spec.start_delay_s >= 0))
    throw std::invalid_argument("motion hold_s and start_delay_s must be >= 0");
  const KeyPoses poses(body_, spec.touch_target_m, shape_of(spec.kind));
  const double move = 1.0 / spec.speed;
  const double hold = spec.hold_s;
  auto retract_from_touch = [&](const KeyPoses& from) {
    add(kLiftS * move, from.lifted());
    add(kLowerToRaisedS * move, from.raised());
    add(kLowerToRestS * move, from.rest());
  };
  switch (spec.kind) {
    case MotionKind::Idle:
      add(0, poses.rest());
      add(kIdleS * move, poses.rest());
      break;
    case MotionKind::Raise:
      add(0, poses.rest());
      add(kRaiseS * move, poses.raised());
      break;
    case MotionKind::Approach:
      add(0, poses.raised());
      add(kApproachS * move, poses.pre_touch());
      break;
    case MotionKind::TouchHold:
      add(0, poses.pre_touch());
      add(kPressS * move, poses.touch());
      add(hold, poses.touch());
      break;
    case MotionKind::Retract:
      add(0, poses.touch());
      retract_from_touch(poses);
      break;
    case MotionKind::Wave:
      add(0, poses.rest());
      add(kRaiseS * move, poses.wave(0));
      for (int stroke = 0; stroke < kWaveStrokes; ++stroke)
        add(kWaveStrokeS * move * (stroke == 0 ? 0.5 : 1.0), poses.wave(stroke % 2 == 0 ? -1 : 1));
      add(kWaveStrokeS * move * 0.5, poses.wave(0));
      add(kLowerToRestS * move, poses.rest());
      break;
    case MotionKind::FastApproach:
      add(0, poses.rest());
      add(kFastReachS * move, poses.pre_touch());
      add(kFastPressS * move, poses.touch());
      add(hold, poses.touch());
      break;
    case MotionKind::Clap:
    case MotionKind::FistBump:
    case MotionKind::FingerTouch:
      add(0, poses.rest());
      add(kRaiseS * move, poses.raised());
      add(kApproachS * move, poses.pre_touch());
      add(kPressS * move, poses.touch());
      add(hold, poses.touch());
      retract_from_touch(poses);
      break;
    case MotionKind::Graze: {
      // On the glass above the target, then down past it: the target is the slide's middle.
      const KeyPoses top(body_, spec.touch_target_m + Eigen::Vector2d(0, kGrazeSlideM / 2));
      const KeyPoses bottom(body_, spec.touch_target_m - Eigen::Vector2d(0, kGrazeSlideM / 2));
      add(0, top.rest());
      add(kRaiseS * move, top.raised());
      add(kApproachS * move, top.pre_touch());
      add(kPressS * move, top.touch());
      add(hold, bottom.touch());
      retract_from_touch(bottom);
      break;
    }
  }
  if (!(spec.repeat_every_s >= 0) || !std::isfinite(spec.repeat_every_s))
    throw std::invalid_argument("motion repeat_every_s must be >= 0");
  if (spec.repeat_every_s > 0 && spec.repeat_every_s < duration_s())
    throw std::invalid_argument("motion repeat_every_s (" + std::to_string(spec.repeat_every_s) +
                                " s) is shorter than the motion itself (" + std::to_string(duration_s()) + " s)");
}

PersonPose MotionTrack::pose_at(double t_s) const {
  if (!std::isfinite(t_s)) throw std::invalid_argument("motion time must be finite");
  const double breath_t_s = t_s;
  if (spec_.repeat_every_s > 0 && t_s > 0) t_s = std::fmod(t_s, spec_.repeat_every_s);
  const auto next = std::upper_bound(keys_.begin(), keys_.end(), t_s,
                                     [](double t, const Keyframe& key) { return t < key.t_s; });
  BodyKey key;
  if (next == keys_.begin()) {
    key = keys_.front().body;
  } else if (next == keys_.end()) {
    key = keys_.back().body;
  } else {
    const Keyframe& previous = *(next - 1);
    const double span = next->t_s - previous.t_s;
    key = span > 0 ? blend(previous.body, next->body, smoothstep((t_s - previous.t_s) / span)) : next->body;
  }
  key.lean_rad += kBreathLeanRad * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * breath_t_s / kBreathPeriodS));
  const uint64_t timestamp_us = breath_t_s > 0 ? uint64_t(std::llround(breath_t_s * 1e6)) : 0;
  return pose_person(body_, key, timestamp_us);
}

PersonPose evaluate_motion(const MotionSpec& spec, const Seat& seat, const UserAppearance& appearance, double t_s) {
  return MotionTrack(spec, seat, appearance).pose_at(t_s);
}

}  // namespace rt::sim
