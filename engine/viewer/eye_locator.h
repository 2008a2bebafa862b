#pragma once
// One frame set of the site's cameras in, the viewer's eyes out: detect the eyes in every view,
// label them with each camera's pose, triangulate. A view without a frame (an empty cv::Mat)
// or without a detected face simply does not take part.
#include <opencv2/core.hpp>

#include <span>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "viewer/eye_detector.h"
#include "viewer/eye_pair.h"

namespace rt {

// The views whose image shows both eyes, labelled by the viewer's side; `misses` gathers why each
// other view does not take part ("; camera 'NAME': why").
std::vector<ViewEyes> detect_eyes_in_views(EyeDetector& detector, std::span<const Camera> cameras,
                                           std::span<const cv::Mat> images, std::string& misses);

// `images[i]` is camera i's color image, distorted as the camera delivers it. A wrong count of
// images is a programming error and throws std::invalid_argument.
EyePair locate_viewer_eyes(EyeDetector& detector, std::span<const Camera> cameras, std::span<const cv::Mat> images,
                           const EyePairLimits& limits = {});

}  // namespace rt
