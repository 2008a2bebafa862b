#include "geometry/pixel_rays.h"

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <limits>

namespace rt {

std::vector<std::array<double, 2>> undistorted_points(const CameraIntrinsics& k,
                                                      const std::vector<std::array<double, 2>>& pixels) {
  std::vector<std::array<double, 2>> rays(pixels.size());
  if (pixels.empty()) return rays;
  std::vector<cv::Point2d> points, normalised;
  points.reserve(pixels.size());
  for (const auto& [x, y] : pixels) points.emplace_back(x, y);
  const auto coefficients = k.distortion.as_opencv();
  cv::undistortPoints(points, normalised, cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1),
                      cv::Mat(int(coefficients.size()), 1, CV_64F, const_cast<double*>(coefficients.data())),
                      cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < normalised.size(); ++i) {
    const cv::Point2d& n = normalised[i];
    rays[i] = std::isfinite(n.x) && std::isfinite(n.y) ? std::array<double, 2>{n.x, n.y} : std::array<double, 2>{nan, nan};
  }
  return rays;
}

std::vector<std::array<float, 2>> undistorted_pixel_rays(const CameraIntrinsics& k) {
  std::vector<std::array<double, 2>> pixels;
  pixels.reserve(size_t(k.width) * k.height);
  for (uint32_t y = 0; y < k.height; ++y)
    for (uint32_t x = 0; x < k.width; ++x) pixels.push_back({double(x), double(y)});
  const std::vector<std::array<double, 2>> normalised = undistorted_points(k, pixels);
  std::vector<std::array<float, 2>> rays(normalised.size());
  for (size_t i = 0; i < normalised.size(); ++i) rays[i] = {float(normalised[i][0]), float(normalised[i][1])};
  return rays;
}

}  // namespace rt
