#pragma once
// The shared virtual space (DESIGN.md section 2, paper section 3.2): each site's frame has its
// origin at the screen centre, +x right as the seated user sees it, +y up, +z towards the user.
// The global frame is site A's; site B maps to it by a 180-degree turn about +y, so the two
// screens coincide and the users face each other through one glass. Every part that moves a
// point, an eye or a skeleton between sites goes through here.
#include <Eigen/Geometry>

#include "tracking/hand_skeleton.h"

namespace rt {

enum class Site { A, B };

Site other_site(Site site);
const char* site_name(Site site);

// global <- site
Eigen::Isometry3d global_from_site(Site site);
// site <- global
Eigen::Isometry3d site_from_global(Site site);
// `to` <- `from`: a point in site `from`'s frame expressed in site `to`'s frame.
Eigen::Isometry3d site_from_site(Site to, Site from);

Eigen::Vector3d map_point(Site from, Site to, const Eigen::Vector3d& point);
Eigen::Vector3d map_direction(Site from, Site to, const Eigen::Vector3d& direction);
// Every joint and direction of a skeleton; timestamps, ids and handedness are kept.
HandSkeleton map_skeleton(Site from, Site to, const HandSkeleton& skeleton);

// The screen rectangle of a site: z = 0, |x| <= width/2, |y| <= height/2.
struct Screen {
  double width_m = 1.439;   // 65-inch 16:9 panel
  double height_m = 0.809;
  bool contains(const Eigen::Vector2d& xy) const;
};

// Distance of a point to the screen plane (|z|), in metres.
double distance_to_screen(const Eigen::Vector3d& point);

}  // namespace rt
