#include "geometry/target_view.h"

#include <stdexcept>
#include <string>

namespace rt {

Camera target_view_camera(const Eigen::Vector3d& eye, const Screen& screen, uint32_t width, uint32_t height) {
  if (!eye.allFinite()) throw std::invalid_argument("target view: the viewer's eye is not finite");
  if (!(eye.z() < 0.0))
    throw std::invalid_argument("target view: the viewer's eye must be in front of their own screen (here z < 0), is at z = " +
                                std::to_string(eye.z()) + " m");
  if (width == 0 || height == 0) throw std::invalid_argument("target view: the image size must be at least 1x1");
  const double distance = -eye.z();
  Camera camera;
  camera.name = "target view";
  CameraIntrinsics& k = camera.intrinsics;
  k.width = width;
  k.height = height;
  // The screen's left edge as the viewer sees it (x = +W/2 here) maps to the image's left
  // border (OpenCV pixel -0.5), its top edge (y = +H/2) to the top border.
  k.fx = width * distance / screen.width_m;
  k.fy = height * distance / screen.height_m;
  k.cx = width * (0.5 - eye.x() / screen.width_m) - 0.5;
  k.cy = height * (0.5 - eye.y() / screen.height_m) - 0.5;
  // Camera axes in the site frame: right = -x, down = -y, forward = +z (a proper rotation).
  Eigen::Isometry3d site_from_camera = Eigen::Isometry3d::Identity();
  site_from_camera.linear() = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
  site_from_camera.translation() = eye;
  camera.camera_from_site = site_from_camera.inverse();
  return camera;
}

}  // namespace rt
