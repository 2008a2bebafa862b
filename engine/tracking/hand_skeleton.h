#pragma once
// One tracked hand in a site frame (metres, DESIGN.md section 2): wrist, palm centre, elbow, and
// for each digit the joints carp, mcp, pip, dip, tip (the thumb's carp equals its mcp: its
// metacarpal has zero length). Tracker-native data is converted into this once, at the device.
// What a tracker may not give is NaN: the elbow (then there is no forearm: nothing is invented),
// the palm's and the forearm's widths.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace rt {

enum class Digit : int { Thumb = 0, Index, Middle, Ring, Pinky };
enum class DigitJoint : int { Carp = 0, Mcp, Pip, Dip, Tip };
inline constexpr int kDigitCount = 5;
inline constexpr int kJointsPerDigit = 5;

struct HandSkeleton {
  uint64_t timestamp_us = 0;  // capture time, monotonic clock
  int32_t id = 0;             // tracker's hand id
  bool is_left = false;
  float confidence = 0.0f;    // 0..1
  Eigen::Vector3d wrist = Eigen::Vector3d::Zero();
  Eigen::Vector3d palm = Eigen::Vector3d::Zero();
  Eigen::Vector3d elbow = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  // NaN: not tracked
  Eigen::Vector3d palm_normal = Eigen::Vector3d::UnitZ();  // unit, out of the palm
  Eigen::Vector3d direction = Eigen::Vector3d::UnitY();    // unit, palm towards the fingers
  std::array<std::array<Eigen::Vector3d, kJointsPerDigit>, kDigitCount> digits{};
  // Widths across the palm (Leap's palmWidth) and across the forearm (armWidth); NaN: not given.
  double palm_width_m = std::numeric_limits<double>::quiet_NaN();
  double arm_width_m = std::numeric_limits<double>::quiet_NaN();

  bool has_elbow() const { return elbow.allFinite(); }

  Eigen::Vector3d& joint(Digit digit, DigitJoint joint) { return digits[int(digit)][int(joint)]; }
  const Eigen::Vector3d& joint(Digit digit, DigitJoint joint) const { return digits[int(digit)][int(joint)]; }

  // Wrist, palm and every digit joint (not the elbow: it is not part of the hand), 27 points.
  std::vector<Eigen::Vector3d> hand_joints() const;
};

// The hand nearest the screen (smallest |palm z|, so that hands mapped into the other site's
// frame, behind its glass, are judged alike): the one reaching for the glass, which the receiver
// draws; null when no hand has a finite palm.
const HandSkeleton* hand_nearest_screen(const std::vector<HandSkeleton>& hands);

}  // namespace rt
