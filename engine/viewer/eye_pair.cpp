#include "viewer/eye_pair.h"

#include <algorithm>
#include <sstream>

namespace rt {

std::optional<EyePixels> assign_viewer_sides(const Camera& camera, const Eigen::Vector2d& eye_a, const Eigen::Vector2d& eye_b,
                                             double nominal_distance_m) {
  if (!eye_a.allFinite() || !eye_b.allFinite() || !(nominal_distance_m > 0) || (eye_a - eye_b).norm() < 1e-6)
    return std::nullopt;
  const Eigen::Vector2d between = (eye_a + eye_b) / 2.0;
  const Eigen::Vector3d near_eyes = camera.position_in_site() + nominal_distance_m * camera.ray_in_site(between);
  // A short step keeps both ends inside the view even near its border.
  const auto here = camera.project(near_eyes);
  const auto rightwards = camera.project(near_eyes + Eigen::Vector3d(0.01, 0.0, 0.0));
  if (!here || !rightwards) return std::nullopt;
  const Eigen::Vector2d site_x_in_image = *rightwards - *here;
  if (site_x_in_image.dot(eye_b - eye_a) > 0.0) return EyePixels{eye_b, eye_a};
  return EyePixels{eye_a, eye_b};
}

namespace {

EyePair failed(ViewerFailure failure, std::string message, std::vector<size_t> cameras_seeing_eyes) {
  EyePair pair;
  pair.failure = failure;
  pair.message = std::move(message);
  pair.cameras_seeing_eyes = std::move(cameras_seeing_eyes);
  return pair;
}

}  // namespace

EyePair triangulate_eye_pair(std::span<const Camera> cameras, std::span<const ViewEyes> views, const EyePairLimits& limits) {
  std::vector<size_t> seeing;
  std::vector<PixelObservation> right_eye, left_eye;
  for (const ViewEyes& view : views) {
    seeing.push_back(view.camera_index);
    right_eye.push_back({view.camera_index, view.eyes.viewer_right});
    left_eye.push_back({view.camera_index, view.eyes.viewer_left});
  }
  const MultiViewPoint right = triangulate_observations(cameras, right_eye, limits.point);
  if (!right.ok()) return failed(right.failure, "viewer's right eye: " + right.message, seeing);
  const MultiViewPoint left = triangulate_observations(cameras, left_eye, limits.point);
  if (!left.ok()) return failed(left.failure, "viewer's left eye: " + left.message, seeing);

  const double eye_distance = (right.point - left.point).norm();
  if (!(eye_distance >= limits.min_eye_distance_m && eye_distance <= limits.max_eye_distance_m)) {
    std::ostringstream message;
    message << "the eyes triangulate " << eye_distance * 1000.0 << " mm apart, outside the human range "
            << limits.min_eye_distance_m * 1000.0 << "-" << limits.max_eye_distance_m * 1000.0
            << " mm: a detection in some view is not an eye";
    return failed(ViewerFailure::EyesImplausible, message.str(), seeing);
  }
  // The viewer's right eye lies on the +x side whatever the head's yaw within a frontal face's
  // range; the other way round means the views labelled the eyes inconsistently.
  if (!(right.point.x() > left.point.x()))
    return failed(ViewerFailure::EyesImplausible,
                  "the viewer's right eye triangulates to the left of the left eye (site x): the views' left/right labels disagree",
                  seeing);

  EyePair pair;
  pair.viewer_right = right.point;
  pair.viewer_left = left.point;
  pair.midpoint = (right.point + left.point) / 2.0;
  pair.max_reprojection_px = std::max(right.max_reprojection_px, left.max_reprojection_px);
  pair.max_reprojection_mrad = std::max(right.max_reprojection_mrad, left.max_reprojection_mrad);
  pair.cameras_seeing_eyes = std::move(seeing);
  pair.cameras_rejected = right.cameras_rejected;
  for (size_t camera : left.cameras_rejected)
    if (std::find(pair.cameras_rejected.begin(), pair.cameras_rejected.end(), camera) == pair.cameras_rejected.end())
      pair.cameras_rejected.push_back(camera);
  return pair;
}

}  // namespace rt
