#pragma once
// A procedural hand: a medium adult hand's joints in its own frame, scaled, curled and placed in
// the site frame as an rt::HandSkeleton (wrist, palm centre, carp/mcp/pip/dip/tip per digit; the
// thumb's metacarpal has zero length, as a Leap-style tracker reports it).
#include <Eigen/Geometry>

#include <array>
#include <cstdint>

#include "tracking/hand_skeleton.h"

namespace rt::sim {

// The hand frame: u = towards the thumb of a right hand (direction x palm normal), v = from the
// wrist along the fingers, w = out of the palm. A left hand is the mirror image (thumb at -u).
struct DigitModel {
  Eigen::Vector2d carp_uv;  // metres, hand_scale 1
  Eigen::Vector2d mcp_uv;
  double splay_deg;                       // finger direction, from v towards u
  std::array<double, 3> phalanges_m;      // proximal, intermediate, distal
  std::array<double, 3> max_flexion_deg;  // at mcp, pip, dip when curl = 1
};
const std::array<DigitModel, kDigitCount>& medium_adult_hand();
// Wrist to middle fingertip, hand_scale 1 (about 0.18 m: a medium adult hand).
double medium_hand_length_m();
double palm_width_m(double hand_scale);
// Palm centre in the hand frame (u, v), hand_scale 1; the wrist is the origin.
Eigen::Vector2d palm_centre_uv();

struct HandPlacement {
  Eigen::Vector3d palm = Eigen::Vector3d::Zero();                   // palm centre, site frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // hand frame (u, v, w) -> site
  double curl = 0.0;  // 0: flat, every joint in the palm plane; 1: a loose fist
  // Added to `curl` per digit (the sum clamped to [0, 1]): a pointing hand curls all but the
  // index finger.
  std::array<double, kDigitCount> extra_curl{};
};

// The rotation whose columns are (direction x palm_normal, direction, palm_normal);
// `palm_normal` is made orthogonal to `direction`.
Eigen::Quaterniond hand_orientation(const Eigen::Vector3d& direction, const Eigen::Vector3d& palm_normal);

HandSkeleton build_hand(const HandPlacement& placement, bool is_left, double hand_scale);

}  // namespace rt::sim
