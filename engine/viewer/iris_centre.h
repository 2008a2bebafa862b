#pragma once
// Refines an eye detection to the iris: a Haar eye box is placed by a coarse scan and its centre
// lies off the pupil by up to a sixth of the box (towards an eye corner or the eyebrow). The
// iris is a dark disc with a strong circular edge, which Timm and Barth's gradient method finds.
#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace rt {

// The iris centre inside the middle of `eye_box`, in pixel-centre coordinates of `grey` (8-bit,
// one channel), to a fraction of a pixel. Falls back to the box centre when the box is too small
// (< 8 px), lies outside the image, or holds no edges.
Eigen::Vector2d iris_centre(const cv::Mat& grey, const cv::Rect& eye_box);

}  // namespace rt
