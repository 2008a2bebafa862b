#include "viewer/simulated_views.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

namespace rt {

Camera camera_looking_at(const std::string& name, const CameraIntrinsics& intrinsics, const Eigen::Vector3d& position,
                         const Eigen::Vector3d& target) {
  Camera camera;
  camera.name = name;
  camera.intrinsics = intrinsics;
  try {
    camera.camera_from_site = sim::camera_from_site_looking_at(position, target);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("camera '" + name + "': " + error.what());
  }
  return camera;
}

std::vector<Camera> simulated_camera_stand(const CameraStandOptions& options) {
  std::vector<Camera> cameras;
  for (const sim::CameraMount& mount : sim::camera_stand_mounts(options.screen, options.stand))
    cameras.push_back(camera_looking_at(mount.name, options.intrinsics, mount.position, options.aim));
  return cameras;
}

namespace {

// Normalised, undistorted camera coordinates (x/z, y/z) of every pixel. Undistortion is an
// iterative solve per point, so it runs on a grid every kGridStep pixels and is interpolated
// bilinearly in between: lens distortion is smooth, the interpolation error stays far below
// a hundredth of a pixel for the mild lenses of RGBD cameras, and it is ~60 times faster.
cv::Mat normalised_coordinates(const Camera& camera) {
  constexpr int kGridStep = 8;
  const CameraIntrinsics& k = camera.intrinsics;
  const int grid_columns = int(k.width + kGridStep - 2) / kGridStep + 1;
  const int grid_rows = int(k.height + kGridStep - 2) / kGridStep + 1;
  std::vector<cv::Point2f> grid_pixels;
  for (int row = 0; row < grid_rows; ++row)
    for (int column = 0; column < grid_columns; ++column)
      grid_pixels.emplace_back(float(column * kGridStep), float(row * kGridStep));
  std::vector<cv::Point2f> grid_normalised;
  const auto coefficients = k.distortion.as_opencv();
  cv::undistortPoints(grid_pixels, grid_normalised, cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1),
                      cv::Mat(int(coefficients.size()), 1, CV_64F, const_cast<double*>(coefficients.data())));
  // By hand rather than cv::remap, whose bilinear weights are quantised to 1/32 of a cell.
  cv::Mat normalised(int(k.height), int(k.width), CV_32FC2);
  for (int v = 0; v < int(k.height); ++v) {
    const int row = std::min(v / kGridStep, grid_rows - 2);
    const float fy = float(v - row * kGridStep) / kGridStep;
    for (int u = 0; u < int(k.width); ++u) {
      const int column = std::min(u / kGridStep, grid_columns - 2);
      const float fx = float(u - column * kGridStep) / kGridStep;
      auto at = [&](int r, int c) { return grid_normalised[size_t(r) * size_t(grid_columns) + size_t(c)]; };
      const cv::Point2f top = at(row, column) * (1 - fx) + at(row, column + 1) * fx;
      const cv::Point2f bottom = at(row + 1, column) * (1 - fx) + at(row + 1, column + 1) * fx;
      const cv::Point2f value = top * (1 - fy) + bottom * fy;
      normalised.at<cv::Vec2f>(v, u) = cv::Vec2f(value.x, value.y);
    }
  }
  return normalised;
}

}  // namespace

Eigen::Vector3d PlanarPhoto::pixel_in_site(const Eigen::Vector2d& pixel) const {
  return site_from_photo * Eigen::Vector3d(pixel.x() * metres_per_pixel, pixel.y() * metres_per_pixel, 0.0);
}

cv::Mat render_planar_photo(const PlanarPhoto& photo, const Camera& camera, const cv::Scalar& background) {
  if (photo.image.empty() || photo.image.depth() != CV_8U) throw std::invalid_argument("render_planar_photo: the photo must be a non-empty 8-bit image");
  if (!(photo.metres_per_pixel > 0)) throw std::invalid_argument("render_planar_photo: metres_per_pixel must be > 0");
  const CameraIntrinsics& k = camera.intrinsics;
  if (k.width < 2 || k.height < 2 || !(k.fx > 0 && k.fy > 0))
    throw std::invalid_argument("render_planar_photo: camera '" + camera.name + "' has no valid intrinsics");

  // Bilinear lookups of a photo much finer than the camera's pixels alias; shrinking it to about
  // one photo pixel per camera pixel first averages like a real sensor would.
  const Eigen::Vector3d centre = photo.pixel_in_site({photo.image.cols / 2.0, photo.image.rows / 2.0});
  const double footprint_m = (centre - camera.position_in_site()).norm() / std::max(k.fx, k.fy);
  const double shrink = footprint_m / photo.metres_per_pixel;
  cv::Mat source = photo.image;
  Eigen::Matrix3d source_to_photo = Eigen::Matrix3d::Identity();
  if (shrink > 1.0) {
    const cv::Size size(std::max(1, int(std::lround(photo.image.cols / shrink))), std::max(1, int(std::lround(photo.image.rows / shrink))));
    cv::resize(photo.image, source, size, 0, 0, cv::INTER_AREA);
    const double fx = double(photo.image.cols) / size.width, fy = double(photo.image.rows) / size.height;
    // Pixel centres map as original = (shrunk + 0.5) * factor - 0.5.
    source_to_photo << fx, 0, 0.5 * fx - 0.5, 0, fy, 0.5 * fy - 0.5, 0, 0, 1;
  }

  // Photo pixel -> normalised camera coordinates is a homography of the plane.
  const Eigen::Isometry3d camera_from_photo = camera.camera_from_site * photo.site_from_photo;
  Eigen::Matrix3d photo_to_camera;
  photo_to_camera.col(0) = camera_from_photo.linear().col(0) * photo.metres_per_pixel;
  photo_to_camera.col(1) = camera_from_photo.linear().col(1) * photo.metres_per_pixel;
  photo_to_camera.col(2) = camera_from_photo.translation();
  const Eigen::Matrix3d camera_to_source = (photo_to_camera * source_to_photo).inverse();

  const cv::Mat undistorted = normalised_coordinates(camera);
  cv::Mat map_x(int(k.height), int(k.width), CV_32F), map_y(int(k.height), int(k.width), CV_32F);
  for (int v = 0; v < int(k.height); ++v)
    for (int u = 0; u < int(k.width); ++u) {
      const cv::Vec2f& n = undistorted.at<cv::Vec2f>(v, u);
      const Eigen::Vector3d q = camera_to_source * Eigen::Vector3d(n[0], n[1], 1.0);
      // q.z = 1 / depth of the plane point: not positive means the plane lies behind the camera.
      const bool in_front = q.z() > 1e-12;
      map_x.at<float>(v, u) = in_front ? float(q.x() / q.z()) : -1e6f;
      map_y.at<float>(v, u) = in_front ? float(q.y() / q.z()) : -1e6f;
    }
  cv::Mat rendered;
  cv::remap(source, rendered, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, background);
  return rendered;
}

}  // namespace rt
