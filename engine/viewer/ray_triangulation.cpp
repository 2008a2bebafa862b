#include "viewer/ray_triangulation.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>
#include <vector>

namespace rt {

namespace {

PointEstimate failed_estimate(ViewerFailure failure, std::string message, int offending_ray = -1) {
  PointEstimate estimate;
  estimate.failure = failure;
  estimate.message = std::move(message);
  estimate.offending_ray = offending_ray;
  return estimate;
}

double largest_pairwise_angle_rad(const std::vector<Eigen::Vector3d>& directions) {
  double largest = 0.0;
  for (size_t i = 0; i < directions.size(); ++i)
    for (size_t j = i + 1; j < directions.size(); ++j) {
      // atan2 of |cross| and dot stays accurate for tiny angles, where acos(dot) does not.
      const double angle = std::atan2(directions[i].cross(directions[j]).norm(), directions[i].dot(directions[j]));
      largest = std::max(largest, angle);
    }
  return largest;
}

}  // namespace

PointEstimate nearest_point_to_rays(std::span<const Ray> rays, const RayTriangulationLimits& limits) {
  if (rays.size() < 2)
    return failed_estimate(ViewerFailure::TooFewViews, "triangulation needs rays from at least 2 views, got " +
                                                  std::to_string(rays.size()));
  std::vector<Eigen::Vector3d> directions;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    if (!ray.origin.allFinite() || !ray.direction.allFinite())
      return failed_estimate(ViewerFailure::InvalidInput, "ray " + std::to_string(i) + " holds a NaN or infinite value", int(i));
    if (!(ray.direction.norm() > 1e-12))
      return failed_estimate(ViewerFailure::InvalidInput, "ray " + std::to_string(i) + " has a zero direction", int(i));
    directions.push_back(ray.direction.normalized());
  }
  const double min_angle_rad = limits.min_ray_angle_deg * std::numbers::pi / 180.0;
  if (const double angle = largest_pairwise_angle_rad(directions); !(angle >= min_angle_rad))
    return failed_estimate(ViewerFailure::RaysNearlyParallel,
                  "the rays are nearly parallel: the widest pair meets at " + std::to_string(angle * 180.0 / std::numbers::pi) +
                      " degrees, below the " + std::to_string(limits.min_ray_angle_deg) + " degrees needed for a depth");

  // Normal equations of sum_i |(I - d_i d_i^T)(p - o_i)|^2: each projector removes the
  // component along its ray, so only perpendicular distances count.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right_side = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - directions[i] * directions[i].transpose();
    normal += projector;
    right_side += projector * rays[i].origin;
  }
  // The angle check bounds the smallest eigenvalue away from zero (>= 1 - cos(angle)); the
  // eigen-solve keeps that visible and cannot divide by zero.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(normal);
  const Eigen::Vector3d eigenvalues = solver.eigenvalues();
  if (solver.info() != Eigen::Success || !(eigenvalues.minCoeff() > 1e-12))
    return failed_estimate(ViewerFailure::RaysNearlyParallel, "the rays do not fix a point (degenerate normal equations)");
  const Eigen::Matrix3d& basis = solver.eigenvectors();
  PointEstimate estimate;
  estimate.point = basis * (basis.transpose() * right_side).cwiseQuotient(eigenvalues);
  if (!estimate.point.allFinite())
    return failed_estimate(ViewerFailure::InvalidInput, "the triangulated point is not finite");

  double squared_distances = 0.0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d offset = estimate.point - rays[i].origin;
    if (!(offset.dot(directions[i]) > 0.0))
      return failed_estimate(ViewerFailure::BehindCamera, "the rays meet behind the origin of ray " + std::to_string(i) +
                                                     " (behind that camera): the detections cannot belong to one point",
                    int(i));
    squared_distances += (offset - offset.dot(directions[i]) * directions[i]).squaredNorm();
  }
  estimate.rms_ray_distance_m = std::sqrt(squared_distances / double(rays.size()));
  return estimate;
}

}  // namespace rt
