#include "viewer/eye_locator.h"

#include <stdexcept>

namespace rt {

std::vector<ViewEyes> detect_eyes_in_views(EyeDetector& detector, std::span<const Camera> cameras,
                                           std::span<const cv::Mat> images, std::string& misses) {
  std::vector<ViewEyes> views;
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (images[i].empty()) continue;
    const EyeDetection detection = detector.detect(images[i]);
    std::optional<EyePixels> labelled;
    if (detection.found()) labelled = assign_viewer_sides(cameras[i], detection.image_left_eye, detection.image_right_eye);
    if (labelled) {
      views.push_back({i, *labelled});
    } else {
      const std::string why = detection.found() ? "the eyes cannot be told apart" : detection.message;
      misses += "; camera '" + cameras[i].name + "': " + why;
    }
  }
  return views;
}

EyePair locate_viewer_eyes(EyeDetector& detector, std::span<const Camera> cameras, std::span<const cv::Mat> images,
                           const EyePairLimits& limits) {
  if (images.size() != cameras.size())
    throw std::invalid_argument("locate_viewer_eyes: " + std::to_string(images.size()) + " images for " +
                                std::to_string(cameras.size()) + " cameras; pass one image per camera (empty for none)");
  std::string misses;
  const std::vector<ViewEyes> views = detect_eyes_in_views(detector, cameras, images, misses);
  if (views.size() < 2) {
    EyePair pair;
    pair.failure = views.empty() ? ViewerFailure::EyesNotFound : ViewerFailure::TooFewViews;
    pair.message = "the eyes were found in " + std::to_string(views.size()) + " view(s), at least 2 are needed" + misses;
    for (const ViewEyes& view : views) pair.cameras_seeing_eyes.push_back(view.camera_index);
    return pair;
  }
  return triangulate_eye_pair(cameras, views, limits);
}

}  // namespace rt
