#include "viewer/eye_detector.h"

#include "viewer/iris_centre.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace rt {

namespace {

// Where the eyes sit inside a frontal-face box, as fractions of its size: roughly 0.3 in from
// each side and 0.4 down (the alt2 box on the frontal photo of test_viewer_renders: 0.35 and
// 0.67 across, 0.40 down). Only a prior for choosing among candidates; kEyeReachInFace absorbs
// the difference between faces.
constexpr double kEyeHeightInFace = 0.40;
constexpr double kEyeInsetInFace = 0.30;
// An eye candidate farther than this (fraction of the face width) from where the eye should sit
// is something else. On the renders an eye seen obliquely, where the face box sits off-centre,
// lay 0.11 away; a false hit on the nose bridge 0.18 away.
constexpr double kEyeReachInFace = 0.17;
// Faces tried per image, largest first: the viewer and a couple of false or background faces.
constexpr size_t kFacesTried = 3;
// The band searched for eyes: below the forehead, above the nose tip.
constexpr double kEyeBandTop = 0.15;
constexpr double kEyeBandBottom = 0.62;

cv::CascadeClassifier load_cascade(const std::filesystem::path& directory, const std::string& file) {
  const std::filesystem::path path = directory / file;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw EyeDetectorSetupError("cascade file '" + path.string() +
                                "' not found: install the Debian package opencv-data (apt-get install opencv-data), "
                                "or set EyeDetectorOptions::cascade_directory to the folder that holds " + file);
  cv::CascadeClassifier cascade;
  bool loaded = false;
  try {
    loaded = cascade.load(path.string()) && !cascade.empty();
  } catch (const cv::Exception&) {
    loaded = false;  // a malformed file: reported below with the fix
  }
  if (!loaded)
    throw EyeDetectorSetupError("cascade file '" + path.string() +
                                "' could not be read as an OpenCV cascade classifier: reinstall opencv-data");
  return cascade;
}

EyeDetection not_found(ViewerFailure failure, std::string message) {
  EyeDetection detection;
  detection.failure = failure;
  detection.message = std::move(message);
  return detection;
}

std::string describe(const cv::Rect& rect) {
  return std::to_string(rect.width) + "x" + std::to_string(rect.height) + " at (" + std::to_string(rect.x) + ", " +
         std::to_string(rect.y) + ")";
}

// Centre of an integer box in pixel-centre coordinates (pixel i covers [i - 0.5, i + 0.5]).
Eigen::Vector2d box_centre(const cv::Rect& box) {
  return {box.x + (box.width - 1) / 2.0, box.y + (box.height - 1) / 2.0};
}

}  // namespace

namespace {

const EyeDetectorOptions& checked(const EyeDetectorOptions& options) {
  if (!(options.face_scale_step > 1.0 && options.eye_scale_step > 1.0))
    throw EyeDetectorSetupError("EyeDetectorOptions::face_scale_step and eye_scale_step must be > 1");
  if (options.min_face_px < 20)
    throw EyeDetectorSetupError("EyeDetectorOptions::min_face_px must be >= 20 (the face cascade's window)");
  if (options.face_search_max_width_px < 4 * options.min_face_px)
    throw EyeDetectorSetupError("EyeDetectorOptions::face_search_max_width_px must be >= 4 * min_face_px");
  if (options.eye_search_face_width_px < 100)
    throw EyeDetectorSetupError("EyeDetectorOptions::eye_search_face_width_px must be >= 100 (eyes need ~20 px)");
  if (options.eye_cascades.empty())
    throw EyeDetectorSetupError("EyeDetectorOptions::eye_cascades must name at least one cascade");
  return options;
}

}  // namespace

EyeDetector::EyeDetector(const EyeDetectorOptions& options)
    : options_(checked(options)), face_(load_cascade(options.cascade_directory, options.face_cascade)) {
  for (const std::string& file : options.eye_cascades) eyes_.push_back(load_cascade(options.cascade_directory, file));
}

EyeDetection EyeDetector::detect(const cv::Mat& image) {
  if (image.empty()) return not_found(ViewerFailure::InvalidInput, "the image is empty");
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3 && image.channels() != 4))
    return not_found(ViewerFailure::InvalidInput, "the image must be 8-bit grey, BGR or BGRA, got type " +
                                                      std::to_string(image.type()));
  cv::Mat grey;
  if (image.channels() == 1) grey = image;
  else cv::cvtColor(image, grey, image.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  const std::vector<cv::Rect> faces = faces_largest_first(grey);
  if (faces.empty()) return not_found(ViewerFailure::EyesNotFound, "no frontal face in the image");
  // A false face (a chessboard, a textured cushion) can be larger than the viewer's; its "eyes"
  // are rarely found, so the next face gets its turn.
  EyeDetection first_failure;
  for (size_t i = 0; i < std::min<size_t>(faces.size(), kFacesTried); ++i) {
    EyeDetection detection = eyes_in_face(grey, faces[i]);
    if (detection.found()) return detection;
    if (i == 0) first_failure = std::move(detection);
  }
  return first_failure;
}

std::vector<cv::Rect> EyeDetector::faces_largest_first(const cv::Mat& grey) {
  const double shrink = std::min(1.0, double(options_.face_search_max_width_px) / grey.cols);
  cv::Mat small = grey;
  if (shrink < 1.0) cv::resize(grey, small, cv::Size(), shrink, shrink, cv::INTER_AREA);
  std::vector<cv::Rect> faces;
  face_.detectMultiScale(small, faces, options_.face_scale_step, options_.face_min_neighbours, cv::CASCADE_SCALE_IMAGE,
                         cv::Size(options_.min_face_px, options_.min_face_px));
  std::sort(faces.begin(), faces.end(), [](const cv::Rect& a, const cv::Rect& b) { return a.area() > b.area(); });
  for (cv::Rect& face : faces)
    face = cv::Rect(int(std::lround(face.x / shrink)), int(std::lround(face.y / shrink)), int(std::lround(face.width / shrink)),
                    int(std::lround(face.height / shrink)));
  return faces;
}

EyeDetection EyeDetector::eyes_in_face(const cv::Mat& grey, const cv::Rect& face) {
  const int band_top = face.y + int(std::lround(kEyeBandTop * face.height));
  const int band_bottom = face.y + int(std::lround(kEyeBandBottom * face.height));
  const cv::Rect band = cv::Rect(face.x, band_top, face.width, band_bottom - band_top) & cv::Rect(0, 0, grey.cols, grey.rows);
  if (band.width < 10 || band.height < 5)
    return not_found(ViewerFailure::EyesNotFound, "the face " + describe(face) + " is cut off by the image border");
  const double scale = double(options_.eye_search_face_width_px) / face.width;
  cv::Mat enlarged;
  cv::resize(grey(band), enlarged, cv::Size(), scale, scale, cv::INTER_LINEAR);
  // Equalising the eye band alone (not the whole image, whose histogram the room dominates)
  // makes the eye cascades' fixed thresholds independent of the face's exposure.
  cv::equalizeHist(enlarged, enlarged);

  // In the enlarged band's pixels from here on.
  const double face_width = options_.eye_search_face_width_px;
  const double face_middle = (face.x + face.width / 2.0 - band.x) * scale;
  auto expected_eye = [&](bool image_left) {
    const double inset = image_left ? kEyeInsetInFace : 1.0 - kEyeInsetInFace;
    return Eigen::Vector2d((face.x + inset * face.width - band.x) * scale, (face.y + kEyeHeightInFace * face.height - band.y) * scale);
  };
  // The candidate nearest where this half's eye should be, if within reach: eyebrows, nostrils
  // and the nose bridge also fire, farther away. One eye per half keeps the two apart.
  auto nearest = [&](const std::vector<cv::Rect>& eyes, bool image_left) -> std::optional<cv::Rect> {
    const Eigen::Vector2d expected = expected_eye(image_left);
    std::optional<cv::Rect> best;
    for (const cv::Rect& eye : eyes) {
      const Eigen::Vector2d centre = box_centre(eye);
      if ((centre.x() < face_middle) != image_left || (centre - expected).norm() > kEyeReachInFace * face_width) continue;
      if (!best || (centre - expected).norm() < (box_centre(*best) - expected).norm()) best = eye;
    }
    return best;
  };
  // The eye cascade's own window is 20 px: smaller scales would not exist, and cutting off
  // the scales just above it costs the real eye the neighbours that confirm it.
  const cv::Size min_eye(int(0.10 * face_width), int(0.10 * face_width));
  const cv::Size max_eye(int(0.45 * face_width), int(0.45 * face_width));
  std::vector<cv::Rect> candidates;
  std::optional<cv::Rect> left_box, right_box;
  for (cv::CascadeClassifier& cascade : eyes_) {
    std::vector<cv::Rect> found;
    cascade.detectMultiScale(enlarged, found, options_.eye_scale_step, options_.eye_min_neighbours, cv::CASCADE_SCALE_IMAGE,
                             min_eye, max_eye);
    candidates.insert(candidates.end(), found.begin(), found.end());
    left_box = nearest(candidates, true);
    right_box = nearest(candidates, false);
    if (left_box && right_box) break;
  }
  if (!left_box || !right_box)
    return not_found(ViewerFailure::EyesNotFound, std::string("face ") + describe(face) + ": no eye found in its image-" +
                                                      (!left_box ? "left" : "right") + " half");

  auto in_image = [&](const cv::Rect& box) {
    const Eigen::Vector2d in_enlarged = options_.refine_to_iris ? iris_centre(enlarged, box) : box_centre(box);
    // cv::resize maps pixel centres as enlarged = (original + 0.5) * scale - 0.5.
    return Eigen::Vector2d((in_enlarged.x() + 0.5) / scale - 0.5 + band.x, (in_enlarged.y() + 0.5) / scale - 0.5 + band.y);
  };
  EyeDetection detection;
  detection.face = face;
  detection.image_left_eye = in_image(*left_box);
  detection.image_right_eye = in_image(*right_box);
  // A real pair is about 0.4 of a face apart; closer means both picks are one eye's edges.
  if ((detection.image_right_eye - detection.image_left_eye).x() < 0.2 * face.width)
    return not_found(ViewerFailure::EyesNotFound, "face " + describe(face) + ": the two eye detections are too close to be a pair");
  return detection;
}

}  // namespace rt
