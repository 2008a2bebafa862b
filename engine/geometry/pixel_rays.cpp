#include "geometry/pixel_rays.h"

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <limits>

namespace rt {

std::vector<std::array<float, 2>> undistorted_pixel_rays(const CameraIntrinsics& k) {
  std::vector<cv::Point2d> pixels;
  pixels.reserve(size_t(k.width) * k.height);
  for (uint32_t y = 0; y < k.height; ++y)
    for (uint32_t x = 0; x < k.width; ++x) pixels.emplace_back(x, y);
  std::vector<std::array<float, 2>> rays(pixels.size());
  if (pixels.empty()) return rays;
  std::vector<cv::Point2d> normalised;
  const auto coefficients = k.distortion.as_opencv();
  cv::undistortPoints(pixels, normalised, cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1),
                      cv::Mat(int(coefficients.size()), 1, CV_64F, const_cast<double*>(coefficients.data())),
                      cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < normalised.size(); ++i) {
    const cv::Point2d& n = normalised[i];
    rays[i] = std::isfinite(n.x) && std::isfinite(n.y) ? std::array<float, 2>{float(n.x), float(n.y)}
                                                       : std::array<float, 2>{nan, nan};
  }
  return rays;
}

}  // namespace rt
