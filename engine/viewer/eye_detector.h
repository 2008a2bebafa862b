#pragma once
// Finds a viewer's two eyes in one color image with OpenCV's Haar cascades (Debian package
// opencv-data): a frontal face first (the largest whose eyes are found: the seated viewer is the
// nearest person), then one eye in each half of its upper part.
// Which eye is the viewer's right depends on how the camera is mounted, so that is decided with
// the camera's calibration (eye_pair.h), not here: this reports the eyes as the image shows them.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/objdetect.hpp>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "viewer/viewer_failure.h"

namespace rt {

// Where Debian's opencv-data installs the cascades.
inline constexpr const char* kDebianCascadeDirectory = "/usr/share/opencv4/haarcascades";

struct EyeDetectorOptions {
  std::filesystem::path cascade_directory = kDebianCascadeDirectory;
  // On OpenCV's ~100 example images (opencv-doc), nearly all without a face, "default" fired on
  // 27 and alt2 on 13 (chessboards, textures) at 3 neighbours; both find the test faces.
  std::string face_cascade = "haarcascade_frontalface_alt2.xml";
  // Tried in this order until each half of the face has an eye near where eyes sit: the plain
  // eye cascade misses some eyes seen obliquely or half-closed, the glasses and per-eye
  // cascades catch most of those.
  std::vector<std::string> eye_cascades = {"haarcascade_eye.xml", "haarcascade_eye_tree_eyeglasses.xml",
                                           "haarcascade_lefteye_2splits.xml", "haarcascade_righteye_2splits.xml"};
  // Faces are searched in a copy shrunk to at most this width (the face cascade needs ~40 px per
  // face, not the sensor's 2560); the eyes are then searched in the full-resolution face.
  int face_search_max_width_px = 640;
  // In the face search copy: a face at 0.7 m spans ~70 px of a 90-degree 640-px-wide view;
  // 40 px still admits a viewer at 1.2 m.
  int min_face_px = 40;
  double face_scale_step = 1.1;
  int face_min_neighbours = 3;
  // The eye search area is small, so a finer pyramid is cheap; at 1.1 the eye cascade misses
  // eyes that fall between two of its scales.
  double eye_scale_step = 1.05;
  int eye_min_neighbours = 3;
  // Eye cascades need ~20 px per eye; a 70-px face has eyes of ~17 px, so the upper face is
  // enlarged to this width before the eye search.
  int eye_search_face_width_px = 200;
  // Move each eye from its Haar box centre to the iris centre found from its edge (iris_centre.h).
  bool refine_to_iris = true;
};

// Thrown at set-up: a cascade file is missing or unreadable.
class EyeDetectorSetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct EyeDetection {
  ViewerFailure failure = ViewerFailure::None;
  std::string message;  // why nothing was found; empty on success
  cv::Rect face;
  // Eye centres in image pixels; "left" is the one with the smaller image x.
  Eigen::Vector2d image_left_eye = Eigen::Vector2d::Zero();
  Eigen::Vector2d image_right_eye = Eigen::Vector2d::Zero();
  bool found() const { return failure == ViewerFailure::None; }
};

// Not thread-safe: OpenCV's cascade classifier keeps scratch state, so use one per thread.
class EyeDetector {
 public:
  // Throws EyeDetectorSetupError naming the missing file and the package that provides it.
  explicit EyeDetector(const EyeDetectorOptions& options = {});

  // Accepts 8-bit grey, BGR or BGRA images.
  EyeDetection detect(const cv::Mat& image);

 private:
  std::vector<cv::Rect> faces_largest_first(const cv::Mat& grey);
  EyeDetection eyes_in_face(const cv::Mat& grey, const cv::Rect& face);

  EyeDetectorOptions options_;
  cv::CascadeClassifier face_;
  std::vector<cv::CascadeClassifier> eyes_;
};

}  // namespace rt
