#pragma once
// One point seen as a pixel in several calibrated views, triangulated in the site frame: pixels
// are undistorted through each camera's model into rays, the rays meet in the least-squares
// sense, and a view whose detection disagrees with the others is dropped when enough remain.
#include <Eigen/Core>

#include <span>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "viewer/ray_triangulation.h"

namespace rt {

struct PixelObservation {
  size_t camera_index = 0;  // into the camera list passed alongside
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // as detected: distorted image coordinates
};

struct MultiViewLimits {
  RayTriangulationLimits rays;
  // A view whose reprojection error exceeds this angle (pixels / focal length) is an outlier, a
  // wrong detection; with three or more views it is dropped. An angle fits every resolution:
  // 10 mrad is 6.4 px at fx = 640 (1280x720, 90 degrees). The eye detector's centres scatter by
  // 2-4 px there, while a picked eye corner or eyebrow is 10-20 px off.
  double max_reprojection_error_mrad = 10.0;
  // The point must lie in front of the screen: z > this (site frame, metres). An eye on or behind
  // the screen plane has no off-axis projection (DESIGN.md section 2), and no seated viewer's eye
  // comes within 5 cm of the panel; a limit of exactly 0 would also let a point that belongs on
  // the plane through on the rounding of its last bit.
  double min_distance_to_screen_m = 0.05;
};

struct MultiViewPoint {
  ViewerFailure failure = ViewerFailure::None;
  std::string message;  // names the cameras involved; empty on success
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // site frame; meaningful only when ok()
  double rms_reprojection_px = 0.0;
  double max_reprojection_px = 0.0;
  double max_reprojection_mrad = 0.0;  // the same as an angle, what the limit applies to
  std::vector<size_t> cameras_used;      // camera indices whose rays made the point
  std::vector<size_t> cameras_rejected;  // dropped as outliers
  bool ok() const { return failure == ViewerFailure::None; }
};

MultiViewPoint triangulate_observations(std::span<const Camera> cameras, std::span<const PixelObservation> observations,
                                        const MultiViewLimits& limits = {});

}  // namespace rt
