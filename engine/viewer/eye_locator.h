#pragma once
// One frame set of the site's cameras in, the viewer's eyes out: detect the eyes in every view,
// label them with each camera's pose, triangulate. A view without a frame (an empty cv::Mat)
// or without a detected face simply does not take part.
#include <opencv2/core.hpp>

#include <span>

#include "geometry/camera.h"
#include "viewer/eye_detector.h"
#include "viewer/eye_pair.h"

namespace rt {

// `images[i]` is camera i's color image, distorted as the camera delivers it. A wrong count of
// images is a programming error and throws std::invalid_argument.
EyePair locate_viewer_eyes(EyeDetector& detector, std::span<const Camera> cameras, std::span<const cv::Mat> images,
                           const EyePairLimits& limits = {});

}  // namespace rt
