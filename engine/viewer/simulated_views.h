#pragma once
// A simulated camera stand and a photograph on a plane seen through it: color images with known
// 3D content for the eye detector, where real cameras are absent (tests, the simulator).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <vector>

#include "geometry/camera.h"
#include "geometry/site_frames.h"
#include "sim/default_site.h"

namespace rt {

// A camera at `position` (site frame) looking at `target`, its image "down" as close to site -y
// as the view direction allows (an upright mount): sim::camera_from_site_looking_at with a name
// and intrinsics. Throws std::invalid_argument, naming the camera, when the view direction is
// vertical or the points coincide.
Camera camera_looking_at(const std::string& name, const CameraIntrinsics& intrinsics, const Eigen::Vector3d& position,
                         const Eigen::Vector3d& target);

struct CameraStandOptions {
  // 640x360 with a 90 x 59 degree field of view: the Azure Kinect's 16:9 color mode, scaled down.
  CameraIntrinsics intrinsics{640, 360, 320.0, 320.0, 319.5, 179.5, {}};
  Screen screen;
  sim::CameraStandGeometry stand;          // the default site's stand
  Eigen::Vector3d aim = {0.0, 0.0, 0.7};  // the seated viewer's head (DESIGN.md section 1)
};

// The six cameras of the site stand (sim::camera_stand_mounts), named "top-left", "top-centre",
// "top-right", "bottom-left", "bottom-centre", "bottom-right" (left/right as the seated user sees them).
std::vector<Camera> simulated_camera_stand(const CameraStandOptions& options = {});

// A photograph as a flat, rectangular object in the site. Photo frame: origin at the centre of
// pixel (0, 0), +x along image columns, +y along image rows, +z = x cross y (into the print when
// the photo faces the viewer of the print).
struct PlanarPhoto {
  cv::Mat image;  // 8-bit, 1, 3 or 4 channels
  double metres_per_pixel = 0.0005;
  Eigen::Isometry3d site_from_photo = Eigen::Isometry3d::Identity();

  Eigen::Vector3d pixel_in_site(const Eigen::Vector2d& pixel) const;
};

// The camera's image of the photo (lens distortion included; aliasing avoided by shrinking the
// photo to about the camera's sampling first); pixels that miss the photo get `background`.
cv::Mat render_planar_photo(const PlanarPhoto& photo, const Camera& camera, const cv::Scalar& background = cv::Scalar::all(96));

}  // namespace rt
