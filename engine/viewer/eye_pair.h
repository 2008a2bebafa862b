#pragma once
// Both eyes of the viewer triangulated from several views, and the viewpoint the renderer needs:
// the midpoint of the two eyes (paper, "Viewpoint Computation"). Site frame, metres.
#include <Eigen/Core>

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "viewer/multiview_point.h"

namespace rt {

// The viewer's own right eye is on the site's +x side (+x is "right as the seated user sees it").
struct EyePixels {
  Eigen::Vector2d viewer_right = Eigen::Vector2d::Zero();
  Eigen::Vector2d viewer_left = Eigen::Vector2d::Zero();
};

// Decides which of two eye pixels in one view is the viewer's right eye from the camera's pose,
// so a camera mounted rolled or upside down labels them correctly. `nominal_distance_m` is a
// rough camera-to-eye distance; only the direction of site +x in the image matters, so any value
// within a factor of a few of the truth gives the same answer. Empty if the eyes are not apart.
std::optional<EyePixels> assign_viewer_sides(const Camera& camera, const Eigen::Vector2d& eye_a, const Eigen::Vector2d& eye_b,
                                             double nominal_distance_m = 0.8);

struct ViewEyes {
  size_t camera_index = 0;
  EyePixels eyes;
};

struct EyePairLimits {
  MultiViewLimits point;
  // Adult interpupillary distances span about 54-74 mm (5th-95th percentile) and children's
  // start near 45 mm; outside 40-90 mm the two "eyes" are not one person's pair.
  double min_eye_distance_m = 0.040;
  double max_eye_distance_m = 0.090;
};

struct EyePair {
  ViewerFailure failure = ViewerFailure::None;
  std::string message;  // says which eye, which cameras; empty on success
  Eigen::Vector3d viewer_right = Eigen::Vector3d::Zero();
  Eigen::Vector3d viewer_left = Eigen::Vector3d::Zero();
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();  // the viewpoint
  double max_reprojection_px = 0.0;                    // over both eyes and all views used
  double max_reprojection_mrad = 0.0;                  // the same as an angle
  std::vector<size_t> cameras_seeing_eyes;             // views whose detector found both eyes
  std::vector<size_t> cameras_rejected;                // dropped as outliers for either eye
  bool ok() const { return failure == ViewerFailure::None; }
};

EyePair triangulate_eye_pair(std::span<const Camera> cameras, std::span<const ViewEyes> views, const EyePairLimits& limits = {});

}  // namespace rt
