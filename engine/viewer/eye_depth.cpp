#include "viewer/eye_depth.h"

#include <stdexcept>

#include "viewer/eye_locator.h"

namespace rt {

std::optional<Eigen::Vector3d> surface_along_ray(const Camera& color, const Camera& depth, const HostImage& depth_mm,
                                                 const Eigen::Vector2d& pixel) {
  if (depth_mm.width != depth.intrinsics.width || depth_mm.height != depth.intrinsics.height) return std::nullopt;
  const Eigen::Vector3d origin = color.position_in_site(), ray = color.ray_in_site(pixel);
  // Millimetre steps: the depth image's own resolution at arm's length is a few millimetres.
  for (double t = 0.2; t <= 3.0; t += 0.001) {
    const Eigen::Vector3d point = origin + t * ray;
    const std::optional<Eigen::Vector2d> at = depth.project(point);
    if (!at) continue;
    const long x = std::lround(at->x()), y = std::lround(at->y());
    if (x < 0 || y < 0 || x >= long(depth_mm.width) || y >= long(depth_mm.height)) continue;
    const float surface_mm = depth_mm.at(uint32_t(x), uint32_t(y));
    if (!(surface_mm > 0)) continue;
    if ((depth.camera_from_site * point).z() * 1000.0 >= surface_mm) return point;
  }
  return std::nullopt;
}

EyePair locate_viewer_eyes_rgbd(EyeDetector& detector, std::span<const Camera> cameras, std::span<const cv::Mat> images,
                                std::span<const Camera> depth_cameras, std::span<const HostImage> depth_images,
                                const EyePairLimits& limits) {
  if (images.size() != cameras.size() || depth_cameras.size() != depth_images.size() ||
      (!depth_cameras.empty() && depth_cameras.size() != cameras.size()))
    throw std::invalid_argument("locate_viewer_eyes_rgbd: " + std::to_string(images.size()) + " images and " +
                                std::to_string(depth_images.size()) + " depth images for " + std::to_string(cameras.size()) +
                                " cameras; pass one of each per camera (empty for none), or no depth at all");
  std::string misses;
  const std::vector<ViewEyes> views = detect_eyes_in_views(detector, cameras, images, misses);
  if (views.size() >= 2) return triangulate_eye_pair(cameras, views, limits);
  EyePair pair;
  for (const ViewEyes& view : views) pair.cameras_seeing_eyes.push_back(view.camera_index);
  if (views.size() == 1 && !depth_cameras.empty()) {
    const size_t k = views[0].camera_index;
    const auto right = surface_along_ray(cameras[k], depth_cameras[k], depth_images[k], views[0].eyes.viewer_right);
    const auto left = surface_along_ray(cameras[k], depth_cameras[k], depth_images[k], views[0].eyes.viewer_left);
    if (right && left) {
      const double apart = (*right - *left).norm();
      if (apart >= limits.min_eye_distance_m && apart <= limits.max_eye_distance_m) {
        pair.viewer_right = *right;
        pair.viewer_left = *left;
        pair.midpoint = (*right + *left) / 2.0;
        return pair;
      }
      pair.failure = ViewerFailure::TooFewViews;
      pair.message = "the eyes were found in 1 view only and its depth puts them " + std::to_string(int(apart * 1000)) +
                     " mm apart, not one person's" + misses;
      return pair;
    }
    misses += "; camera '" + cameras[k].name + "': no depth behind the eyes";
  }
  pair.failure = views.empty() ? ViewerFailure::EyesNotFound : ViewerFailure::TooFewViews;
  pair.message = "the eyes were found in " + std::to_string(views.size()) + " view(s), at least 2 are needed" +
                 (depth_cameras.empty() ? "" : " (or 1 with depth)") + misses;
  return pair;
}

}  // namespace rt
