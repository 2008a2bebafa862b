#include "viewer/multiview_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rt {

namespace {

MultiViewPoint failed_point(ViewerFailure failure, std::string message) {
  MultiViewPoint result;
  result.failure = failure;
  result.message = std::move(message);
  return result;
}

std::string quoted_name(const Camera& camera) { return "camera '" + camera.name + "'"; }

std::string number(double value, int precision = 3) {
  std::ostringstream out;
  out.precision(precision);
  out << value;
  return out.str();
}

// The observations a subset of indices picks, triangulated and checked against the site.
MultiViewPoint solve_subset(std::span<const Camera> cameras, std::span<const PixelObservation> observations,
                            const std::vector<size_t>& subset, const MultiViewLimits& limits) {
  std::vector<Ray> rays;
  for (size_t index : subset) {
    const PixelObservation& observation = observations[index];
    const Camera& camera = cameras[observation.camera_index];
    rays.push_back({camera.position_in_site(), camera.ray_in_site(observation.pixel)});
  }
  const PointEstimate estimate = nearest_point_to_rays(rays, limits.rays);
  if (!estimate.ok()) {
    std::string message = estimate.message;
    if (estimate.offending_ray >= 0)
      message = quoted_name(cameras[observations[subset[size_t(estimate.offending_ray)]].camera_index]) + ": " + message;
    return failed_point(estimate.failure, message);
  }

  MultiViewPoint result;
  result.point = estimate.point;
  double squared_errors = 0.0;
  for (size_t index : subset) {
    const PixelObservation& observation = observations[index];
    const Camera& camera = cameras[observation.camera_index];
    const std::optional<Eigen::Vector2d> reprojected = camera.project(estimate.point);
    if (!reprojected)
      return failed_point(ViewerFailure::BehindCamera, quoted_name(camera) + ": the triangulated point lies behind the camera");
    const double error = (*reprojected - observation.pixel).norm();
    squared_errors += error * error;
    result.max_reprojection_px = std::max(result.max_reprojection_px, error);
    const double focal = (camera.intrinsics.fx + camera.intrinsics.fy) / 2.0;
    result.max_reprojection_mrad = std::max(result.max_reprojection_mrad, 1000.0 * error / focal);
    result.cameras_used.push_back(observation.camera_index);
  }
  result.rms_reprojection_px = std::sqrt(squared_errors / double(subset.size()));
  if (!(result.point.z() > limits.min_distance_to_screen_m))
    return failed_point(ViewerFailure::NotInFrontOfScreen,
                  "the triangulated point lies at z = " + number(result.point.z()) +
                      " m: an eye must be in front of the screen (site z > " + number(limits.min_distance_to_screen_m) +
                      " m; z <= 0 is on or behind the screen plane)");
  return result;
}

bool acceptable(const MultiViewPoint& result, const MultiViewLimits& limits) {
  return result.ok() && result.max_reprojection_mrad <= limits.max_reprojection_error_mrad;
}

// Prefers a solution over a failure, then the smaller largest reprojection error.
bool better(const MultiViewPoint& candidate, const MultiViewPoint& incumbent) {
  if (candidate.ok() != incumbent.ok()) return candidate.ok();
  return candidate.max_reprojection_mrad < incumbent.max_reprojection_mrad;
}

std::string check_input(std::span<const Camera> cameras, std::span<const PixelObservation> observations) {
  std::vector<size_t> seen;
  for (const PixelObservation& observation : observations) {
    if (observation.camera_index >= cameras.size())
      return "observation names camera " + std::to_string(observation.camera_index) + " but only " +
             std::to_string(cameras.size()) + " cameras were given";
    const Camera& camera = cameras[observation.camera_index];
    if (std::find(seen.begin(), seen.end(), observation.camera_index) != seen.end())
      return quoted_name(camera) + " has more than one observation of the same point";
    seen.push_back(observation.camera_index);
    if (!observation.pixel.allFinite()) return quoted_name(camera) + ": the pixel holds a NaN or infinite value";
    const CameraIntrinsics& k = camera.intrinsics;
    if (!(k.fx > 0 && k.fy > 0)) return quoted_name(camera) + ": focal lengths must be > 0";
    const Eigen::Vector2d& p = observation.pixel;
    if (k.width > 0 && k.height > 0 && (p.x() < -0.5 || p.y() < -0.5 || p.x() > k.width - 0.5 || p.y() > k.height - 0.5))
      return quoted_name(camera) + ": pixel (" + number(p.x(), 6) + ", " + number(p.y(), 6) + ") lies outside the " +
             std::to_string(k.width) + "x" + std::to_string(k.height) + " image";
  }
  return {};
}

}  // namespace

MultiViewPoint triangulate_observations(std::span<const Camera> cameras, std::span<const PixelObservation> observations,
                                        const MultiViewLimits& limits) {
  if (std::string problem = check_input(cameras, observations); !problem.empty())
    return failed_point(ViewerFailure::InvalidInput, problem);
  if (observations.size() < 2) {
    std::string message = "a point needs at least 2 views, got " + std::to_string(observations.size());
    if (observations.size() == 1) message += " (" + quoted_name(cameras[observations[0].camera_index]) + ")";
    return failed_point(ViewerFailure::TooFewViews, message);
  }

  std::vector<size_t> subset(observations.size());
  for (size_t i = 0; i < subset.size(); ++i) subset[i] = i;
  MultiViewPoint best = solve_subset(cameras, observations, subset, limits);
  std::vector<size_t> rejected;
  // Greedy leave-one-out: one wrong detection (an eyebrow, a nostril) drags the least-squares
  // point, so the view whose removal best restores agreement goes first. Two views are the
  // minimum that still check each other, so removal stops there.
  while (!acceptable(best, limits) && subset.size() >= 3) {
    MultiViewPoint candidate_best = failed_point(ViewerFailure::TooFewViews, "no subset");
    size_t removed = 0;
    for (size_t drop = 0; drop < subset.size(); ++drop) {
      std::vector<size_t> smaller = subset;
      smaller.erase(smaller.begin() + std::ptrdiff_t(drop));
      MultiViewPoint candidate = solve_subset(cameras, observations, smaller, limits);
      if (better(candidate, candidate_best)) {
        candidate_best = std::move(candidate);
        removed = drop;
      }
    }
    if (!candidate_best.ok()) break;
    rejected.push_back(observations[subset[removed]].camera_index);
    subset.erase(subset.begin() + std::ptrdiff_t(removed));
    best = std::move(candidate_best);
  }
  if (best.ok() && best.max_reprojection_mrad > limits.max_reprojection_error_mrad) {
    std::string names;
    for (size_t camera_index : best.cameras_used) names += (names.empty() ? "" : ", ") + quoted_name(cameras[camera_index]);
    return failed_point(ViewerFailure::ReprojectionTooLarge,
                  "the views disagree (" + names + "): the point reprojects up to " + number(best.max_reprojection_px) +
                      " px (" + number(best.max_reprojection_mrad) + " mrad) from the detections, above the " +
                      number(limits.max_reprojection_error_mrad) + " mrad limit");
  }
  best.cameras_rejected = rejected;
  return best;
}

}  // namespace rt
