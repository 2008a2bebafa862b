#pragma once
// One frame as a Leap-style hand tracker reports it, in its own space: millimetres, y up out of
// the device, origin on the device (DESIGN.md section 6). This is the data on the device side
// of the boundary; tracker_space.h converts it into site-frame skeletons.
#include <Eigen/Core>

#include <array>
#include <optional>
#include <cstdint>
#include <vector>

#include "tracking/hand_skeleton.h"

namespace rt::sim {

struct TrackerDigit {
  // Leap's joints along the digit: carp, mcp, pip, dip and the distal bone's tip (btip); `tip`
  // is the fingertip the tracker reports for pointing (the same point in our simulation).
  Eigen::Vector3d carp = Eigen::Vector3d::Zero();
  Eigen::Vector3d mcp = Eigen::Vector3d::Zero();
  Eigen::Vector3d pip = Eigen::Vector3d::Zero();
  Eigen::Vector3d dip = Eigen::Vector3d::Zero();
  Eigen::Vector3d btip = Eigen::Vector3d::Zero();
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  bool operator==(const TrackerDigit&) const = default;
};

struct TrackerHand {
  int32_t id = 0;  // stays the same while the hand is tracked; a new one after tracking is lost
  bool is_left = false;
  double confidence = 1.0;
  Eigen::Vector3d palm_position = Eigen::Vector3d::Zero();  // mm
  Eigen::Vector3d palm_normal = -Eigen::Vector3d::UnitY();  // unit
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();    // unit, palm towards the fingers
  Eigen::Vector3d wrist = Eigen::Vector3d::Zero();          // mm
  std::optional<Eigen::Vector3d> elbow = Eigen::Vector3d::Zero();  // mm; a real v6 frame may lack it
  std::optional<double> palm_width = 85.0;                  // mm; some service versions leave it out
  std::optional<double> arm_width;                          // mm; only some service versions send it
  std::array<TrackerDigit, kDigitCount> digits{};           // thumb .. pinky (Leap's pointable type 0..4)
  bool operator==(const TrackerHand&) const = default;
};

struct TrackerFrame {
  int64_t id = 0;
  uint64_t timestamp_us = 0;
  std::vector<TrackerHand> hands;  // empty while no hand is tracked
  bool operator==(const TrackerFrame&) const = default;
};

}  // namespace rt::sim
