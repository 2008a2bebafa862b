#pragma once
// A camera's position in the site frame from its measured distances to the four screen corners
// (the paper's device calibration): linear least squares over the four spheres. The corners
// are coplanar, so the distances fix the position up to a mirror image through the screen
// plane; the cameras stand in front of the screen (on the user's side, z >= 0).
#include <Eigen/Core>

#include <array>
#include <string>

#include "geometry/site_frames.h"

namespace rt::calibration {

enum class ScreenCorner { TopLeft, TopRight, BottomRight, BottomLeft };
constexpr std::array<ScreenCorner, 4> kScreenCorners = {ScreenCorner::TopLeft, ScreenCorner::TopRight,
                                                        ScreenCorner::BottomRight, ScreenCorner::BottomLeft};

// "top_left" ... as the seated user sees the screen (+x to the user's right).
const char* corner_name(ScreenCorner corner);
Eigen::Vector3d corner_position(const Screen& screen, ScreenCorner corner);

// A tape measure is good to a few millimetres; a corner off by more than this means a
// mis-read or mis-assigned distance rather than noise.
constexpr double kMaxCornerDistanceResidualM = 0.02;

using CornerDistances = std::array<double, 4>;  // metres, indexed by ScreenCorner

struct Trilateration {
  Eigen::Vector3d position_in_site = Eigen::Vector3d::Zero();
  CornerDistances residuals_m{};  // |position - corner| - measured distance
};

// `camera` names the camera in errors. Throws when a distance is not a positive finite number
// or no point lies within `max_residual_m` of every measured distance.
Trilateration trilaterate(const CornerDistances& distances, const Screen& screen, const std::string& camera,
                          double max_residual_m = kMaxCornerDistanceResidualM);

}  // namespace rt::calibration
