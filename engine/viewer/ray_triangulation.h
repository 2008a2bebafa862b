#pragma once
// The point nearest to a bundle of rays in the least-squares sense: it minimises the sum of
// squared perpendicular distances to the rays. Works in any frame; the rays' origins are the
// camera centres, so "behind a ray" means "behind that camera".
#include <Eigen/Core>

#include <span>
#include <string>

#include "viewer/viewer_failure.h"

namespace rt {

struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // any length > 0; normalised inside
};

struct RayTriangulationLimits {
  // Two rays closer than this to parallel give no usable depth: with 1 mrad of ray noise the
  // depth error grows like noise / sin(angle), about 3 cm at 0.7 m for 2 degrees. The site's
  // cameras see a viewer at 0.7 m under 30 to 90 degrees, so a real stand never comes close.
  double min_ray_angle_deg = 2.0;
};

struct PointEstimate {
  ViewerFailure failure = ViewerFailure::None;
  std::string message;  // what went wrong and with which ray; empty on success
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // meaningful only when ok()
  double rms_ray_distance_m = 0.0;                   // how well the rays agree
  int offending_ray = -1;  // the ray a BehindCamera or InvalidInput failure is about, else -1
  bool ok() const { return failure == ViewerFailure::None; }
};

PointEstimate nearest_point_to_rays(std::span<const Ray> rays, const RayTriangulationLimits& limits = {});

}  // namespace rt
