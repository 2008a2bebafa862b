#include "sim/face.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace rt::sim {
namespace {

// Pupil centres in the default photo (584x824), marked by hand on 12x enlargements (pixel-centre
// coordinates, about +-1 px); the person's right eye is on the image's left.
const Eigen::Vector2d kPhotoRightPupil(244.0, 363.5);
const Eigen::Vector2d kPhotoLeftPupil(365.0, 356.0);
constexpr int kPhotoWidth = 584, kPhotoHeight = 824;
// The adult mean distance between the pupils: the photo's scale on the head.
constexpr double kInterpupillaryM = 0.063;
// The pupils' height above the head centre: the capsule's straight part, where the head is widest.
constexpr double kEyeHeightM = 0.015;
// The face in the photo, an ellipse from the hairline to the chin and cheek to cheek (photo
// pixels); what lies outside (hair, ears, background, collar) is the plain skin of the head.
const Eigen::Vector2d kFaceCentre(305.0, 410.0);
const Eigen::Vector2d kFaceSemiAxes(125.0, 185.0);
constexpr double kFadeFrom = 0.8;  // of the ellipse's radius: fully the photo inside, skin beyond 1
// The texture is the ellipse's bounding box and a margin of zero alpha, so that clamping at the
// texture's edge (every head point outside the face samples the edge) shows skin.
constexpr int kMargin = 4;
const int kCropX0 = int(kFaceCentre.x() - kFaceSemiAxes.x()) - kMargin;
const int kCropY0 = int(kFaceCentre.y() - kFaceSemiAxes.y()) - kMargin;
const int kCropWidth = int(2 * kFaceSemiAxes.x()) + 2 * kMargin + 1;
const int kCropHeight = int(2 * kFaceSemiAxes.y()) + 2 * kMargin + 1;
// Forehead skin, free of eyebrows and hair: the photo's skin color.
const cv::Rect kSkinPatch(270, 250, 70, 50);

double metres_per_photo_pixel() { return kInterpupillaryM / (kPhotoRightPupil - kPhotoLeftPupil).norm(); }
Eigen::Vector2d pupils_midpoint() { return (kPhotoRightPupil + kPhotoLeftPupil) / 2.0; }

// Photo pixel of a head-frame point, and back (on the plane z = 0).
Eigen::Vector2d photo_pixel(const Eigen::Vector3d& head_point) {
  const double scale = metres_per_photo_pixel();
  // The user's right (+x) is the image's left; up (+y) is the image's up.
  return pupils_midpoint() + Eigen::Vector2d(-head_point.x(), -(head_point.y() - kEyeHeightM)) / scale;
}
Eigen::Vector2d head_xy(const Eigen::Vector2d& pixel) {
  const Eigen::Vector2d d = (pixel - pupils_midpoint()) * metres_per_photo_pixel();
  return {-d.x(), kEyeHeightM - d.y()};
}

// The head's front surface at head-frame (x, y): the z of the capsule there (negative, facing
// the screen), as person_mesh draws it.
double front_surface_z(double x, double y, const HeadShape& shape) {
  const double cap = std::min(shape.width_radius_m, shape.depth_radius_m);
  const double beyond = std::max(0.0, std::abs(y) - shape.half_length_m);
  const double ring = std::sqrt(std::max(0.0, 1.0 - std::pow(std::min(beyond / cap, 1.0), 2)));
  const double across = std::clamp(x / (shape.width_radius_m * std::max(ring, 1e-9)), -1.0, 1.0);
  return -shape.depth_radius_m * ring * std::sqrt(1.0 - across * across);
}

TrueEyes eyes_on_head(const Eigen::Vector3d& centre, const Eigen::Matrix3d& rotation, const HeadShape& shape) {
  auto on_head = [&](const Eigen::Vector2d& pixel) {
    const Eigen::Vector2d xy = head_xy(pixel);
    return Eigen::Vector3d(centre + rotation * Eigen::Vector3d(xy.x(), xy.y(), front_surface_z(xy.x(), xy.y(), shape)));
  };
  return {on_head(kPhotoRightPupil), on_head(kPhotoLeftPupil)};
}

}  // namespace

std::filesystem::path face_photo_path() {
  const char* override_path = std::getenv("REMOTETOUCH_FACE_PHOTO");
  return override_path && *override_path ? override_path : kDefaultFacePhoto;
}

HeadShape head_shape(double head_radius_m) { return {0.02, 0.85 * head_radius_m, head_radius_m}; }

std::optional<HostImage> load_face_texture(std::string& why) {
  const std::filesystem::path path = face_photo_path();
  const cv::Mat photo = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (photo.empty()) {
    why = "the face photograph '" + path.string() + "' is missing or unreadable (install the Debian package opencv-doc)";
    return std::nullopt;
  }
  if (photo.cols != kPhotoWidth || photo.rows != kPhotoHeight) {
    why = "the face photograph '" + path.string() + "' is " + std::to_string(photo.cols) + "x" + std::to_string(photo.rows) +
          ", not the " + std::to_string(kPhotoWidth) + "x" + std::to_string(kPhotoHeight) + " photo whose pupils are marked";
    return std::nullopt;
  }
  const cv::Scalar skin_bgr = cv::mean(photo(kSkinPatch));
  HostImage texture(uint32_t(kCropWidth), uint32_t(kCropHeight), PixelFormat::RGBA32F);
  for (int y = 0; y < kCropHeight; ++y)
    for (int x = 0; x < kCropWidth; ++x) {
      const int px = kCropX0 + x, py = kCropY0 + y;
      const Eigen::Vector2d offset = (Eigen::Vector2d(px, py) - kFaceCentre).cwiseQuotient(kFaceSemiAxes);
      const double t = std::clamp((1.0 - offset.norm()) / (1.0 - kFadeFrom), 0.0, 1.0);
      const double alpha = t * t * (3 - 2 * t);  // smoothstep: no visible seam on the head
      const cv::Vec3b bgr = photo.at<cv::Vec3b>(std::clamp(py, 0, photo.rows - 1), std::clamp(px, 0, photo.cols - 1));
      for (int c = 0; c < 3; ++c) texture.at(uint32_t(x), uint32_t(y), uint32_t(c)) = float(bgr[2 - c] / skin_bgr[2 - c]);
      texture.at(uint32_t(x), uint32_t(y), 3) = float(alpha);
    }
  return texture;
}

Eigen::Vector2d face_uv(const Eigen::Vector3d& head_point) {
  const Eigen::Vector2d pixel = photo_pixel(head_point);
  return {(pixel.x() - kCropX0 + 0.5) / kCropWidth, (pixel.y() - kCropY0 + 0.5) / kCropHeight};
}

double face_facing(const Eigen::Vector3d& head_point, const HeadShape& shape) {
  // -z over the depth radius: 1 straight ahead, 0 at the sides; the face ends well before 0.5.
  return std::clamp((-head_point.z() / shape.depth_radius_m - 0.2) / 0.3, 0.0, 1.0);
}

TrueEyes true_eyes(const PersonPose& pose) {
  return eyes_on_head(pose.head_centre, pose.head_rotation, head_shape(pose.head_radius_m));
}

TrueEyes true_eyes_seated(const Eigen::Vector3d& head_centre_m, double head_radius_m) {
  return eyes_on_head(head_centre_m, Eigen::Matrix3d::Identity(), head_shape(head_radius_m));
}

}  // namespace rt::sim
