#pragma once
// The rigid transform (rotation and translation, no scale, never a reflection) that best maps
// one set of corresponding 3D points onto another in the least-squares sense (Umeyama 1991,
// through Eigen::umeyama), with the checks that make its result trustworthy.
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace rt::calibration {

// Points closer than this (RMS) to their best-fitting line leave the rotation about that line
// to the noise: with millimetre noise a 5 cm spread still pins it to about a degree.
constexpr double kMinOffLineSpreadM = 0.05;

struct RigidFit {
  Eigen::Isometry3d target_from_source = Eigen::Isometry3d::Identity();
  std::vector<double> residuals;  // |target_i - T source_i|, in the points' unit, per pair
  double rms() const;
};

// RMS distance of the points to their best-fitting line (0 for fewer than two points).
double off_line_spread(const std::vector<Eigen::Vector3d>& points);

// `what` names the points in errors, e.g. "the cameras' positions". Throws when there are
// fewer than 3 pairs, the counts differ, a point is not finite, or either set is collinear
// (off_line_spread below `min_off_line_spread`, in the points' unit). Coplanar sets are fine:
// the reflection that also fits them is excluded.
RigidFit fit_rigid(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                   const std::string& what, double min_off_line_spread = kMinOffLineSpreadM);

}  // namespace rt::calibration
