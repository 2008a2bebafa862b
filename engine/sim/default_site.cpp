#include "sim/default_site.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace rt::sim {

namespace {

// Azure Kinect: color 16:9 mode about 90 x 59 degrees; depth WFOV 2x2 binned, 512x512, 120 degrees.
constexpr double kColorHorizontalFovDeg = 90.0;
constexpr uint32_t kDepthSize = 512;
constexpr double kDepthFovDeg = 120.0;
constexpr double kDepthMinM = 0.25, kDepthMaxM = 2.88;

// The top row aims between face and chest, so that both stay in view when the user leans in.
// The bottom row aims at the waist: aimed at the face too, the six 59-degree-tall views left the
// bottom of the torso, which the remote eye sees through the lower part of the screen, to no
// color camera at all (a tenth of the portrait, and most of its error).
constexpr double kTopAimBelowHeadM = 0.1;
constexpr double kBottomAimBelowHeadM = 0.5;

constexpr double kTrackerDistanceFromScreenM = 0.5;
// Beside and below the right hand as it reaches for the touch region.
const Eigen::Vector2d kTrackerXY(0.2, -0.3);
// The tracker's axis points at the touch region, a little above the glass, where hands are.
constexpr double kTrackerAimHeightM = 0.07;

// Where a camera at `mount_position` looks: from the top row between the seated user's face and
// chest, from the bottom row (below the screen centre) at the waist.
Eigen::Vector3d camera_aim_point(const Seat& seat, const Eigen::Vector3d& mount_position) {
  const double below_head = mount_position.y() < 0 ? kBottomAimBelowHeadM : kTopAimBelowHeadM;
  return seat.head_centre_m - Eigen::Vector3d(0, below_head, 0);
}

}  // namespace

std::vector<CameraMount> camera_stand_mounts(const Screen& screen, const CameraStandGeometry& geometry) {
  const double x = screen.width_m / 2 + geometry.beyond_edge_m;
  const double y = screen.height_m / 2 + geometry.beyond_edge_m;
  const double z = geometry.in_front_m;
  // x is the site's +x, the seated user's right.
  return {{"top-left", {-x, y, z}},     {"top-centre", {0, y, z}},     {"top-right", {x, y, z}},
          {"bottom-left", {-x, -y, z}}, {"bottom-centre", {0, -y, z}}, {"bottom-right", {x, -y, z}}};
}

Eigen::Isometry3d camera_from_site_looking_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  const Eigen::Vector3d to_target = target - position;
  if (!to_target.allFinite() || to_target.norm() < 1e-9)
    throw std::invalid_argument("camera position and target coincide or are not finite");
  const Eigen::Vector3d forward = to_target.normalized();
  // OpenCV axes: x right, y down. Right = forward x up keeps the image upright.
  const Eigen::Vector3d right_unnormalised = forward.cross(Eigen::Vector3d::UnitY());
  if (right_unnormalised.norm() < 1e-6)
    throw std::invalid_argument("the camera looks straight up or down, its roll is undefined");
  const Eigen::Vector3d right = right_unnormalised.normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d site_from_camera;
  site_from_camera << right, down, forward;
  Eigen::Isometry3d site_from_camera_pose = Eigen::Isometry3d::Identity();
  site_from_camera_pose.linear() = site_from_camera;
  site_from_camera_pose.translation() = position;
  return site_from_camera_pose.inverse();
}

CameraIntrinsics intrinsics_for_horizontal_fov(uint32_t width, uint32_t height, double horizontal_fov_deg) {
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.5 * width / std::tan(0.5 * horizontal_fov_deg * std::numbers::pi / 180.0);
  // Pixel centres at integer coordinates (OpenCV), so the centre of the image is (size - 1) / 2.
  k.cx = 0.5 * (width - 1.0);
  k.cy = 0.5 * (height - 1.0);
  return k;
}

SiteDescription make_default_site(const DefaultSiteOptions& options) {
  SiteDescription site;
  site.name = options.name;
  for (const CameraMount& mount : camera_stand_mounts(site.screen, options.stand)) {
    RgbdCamera camera;
    camera.name = mount.name;
    camera.camera_from_site = camera_from_site_looking_at(mount.position, camera_aim_point(site.seat, mount.position));
    camera.color = intrinsics_for_horizontal_fov(options.color_width, options.color_height, kColorHorizontalFovDeg);
    camera.depth = intrinsics_for_horizontal_fov(kDepthSize, kDepthSize, kDepthFovDeg);
    camera.depth_min_m = kDepthMinM;
    camera.depth_max_m = kDepthMaxM;
    site.cameras.push_back(camera);
  }

  const Eigen::Vector3d tracker_position(kTrackerXY.x(), kTrackerXY.y(), kTrackerDistanceFromScreenM);
  const Eigen::Vector3d tracker_aim(site.touch_region.centre_m.x(), site.touch_region.centre_m.y(), kTrackerAimHeightM);
  const Eigen::Vector3d up = (tracker_aim - tracker_position).normalized();
  const Eigen::Vector3d right = (Eigen::Vector3d::UnitX() - up * up.x()).normalized();
  const Eigen::Vector3d towards_user = right.cross(up);
  Eigen::Isometry3d site_from_tracker = Eigen::Isometry3d::Identity();
  site_from_tracker.linear() << right, up, towards_user;
  site_from_tracker.translation() = tracker_position;
  site.tracker.site_from_tracker = site_from_tracker;

  site.motor_position_m = {-site.screen.width_m / 2, site.screen.height_m / 2, 0.0};
  return site;
}

const std::vector<ShippedSite>& shipped_sites() {
  static const std::vector<ShippedSite> sites{
      {"default.json", {"default", 1280, 720, {}}},
      {"paper.json", {"paper", 2560, 1440, {}}},
  };
  return sites;
}

}  // namespace rt::sim
