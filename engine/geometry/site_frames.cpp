#include "geometry/site_frames.h"

#include <cmath>

namespace rt {

Site other_site(Site site) { return site == Site::A ? Site::B : Site::A; }

const char* site_name(Site site) { return site == Site::A ? "A" : "B"; }

Eigen::Isometry3d global_from_site(Site site) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  if (site == Site::B) transform.linear() = Eigen::Vector3d(-1.0, 1.0, -1.0).asDiagonal();  // (x,y,z) -> (-x,y,-z)
  return transform;
}

Eigen::Isometry3d site_from_global(Site site) { return global_from_site(site).inverse(); }

Eigen::Isometry3d site_from_site(Site to, Site from) { return site_from_global(to) * global_from_site(from); }

Eigen::Vector3d map_point(Site from, Site to, const Eigen::Vector3d& point) { return site_from_site(to, from) * point; }

Eigen::Vector3d map_direction(Site from, Site to, const Eigen::Vector3d& direction) {
  return site_from_site(to, from).linear() * direction;
}

HandSkeleton map_skeleton(Site from, Site to, const HandSkeleton& skeleton) {
  const Eigen::Isometry3d transform = site_from_site(to, from);
  HandSkeleton mapped = skeleton;
  mapped.wrist = transform * skeleton.wrist;
  mapped.palm = transform * skeleton.palm;
  mapped.elbow = transform * skeleton.elbow;
  mapped.palm_normal = transform.linear() * skeleton.palm_normal;
  mapped.direction = transform.linear() * skeleton.direction;
  for (int d = 0; d < kDigitCount; ++d)
    for (int j = 0; j < kJointsPerDigit; ++j) mapped.digits[d][j] = transform * skeleton.digits[d][j];
  return mapped;
}

bool Screen::contains(const Eigen::Vector2d& xy) const {
  return std::abs(xy.x()) <= width_m / 2 && std::abs(xy.y()) <= height_m / 2;
}

double distance_to_screen(const Eigen::Vector3d& point) { return std::abs(point.z()); }

}  // namespace rt
