#pragma once
// The site description the project ships (assets/sites/*.json) comes from this code, so that a
// change of layout is made here and the files are regenerated, never edited by hand:
// the hidden test `remotetouch_cpu_tests "[.regenerate]"` (or `cmake --build <dir> --target
// regenerate_sim_sites`) rewrites them, and the test "shipped site files match the generator"
// fails while they differ.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/site_description.h"

namespace rt::sim {

// Where the stand holds the cameras: just outside the panel's bezel, slightly in front of the glass.
struct CameraStandGeometry {
  double beyond_edge_m = 0.04;
  double in_front_m = 0.03;
};

// One camera place on the stand, named as the seated user sees it ("top-left": site -x, +y).
struct CameraMount {
  std::string name;
  Eigen::Vector3d position;  // site frame, metres
};

// The six places of DESIGN.md section 1, in this order: "top-left", "top-centre", "top-right",
// "bottom-left", "bottom-centre", "bottom-right". The one definition of the stand: the default
// site, the calibration's synthetic site and the viewer's simulated views all take it from here.
std::vector<CameraMount> camera_stand_mounts(const Screen& screen, const CameraStandGeometry& geometry = {});

struct DefaultSiteOptions {
  std::string name = "default";
  // 16:9 color; the paper records 2560x1440, 1280x720 keeps the simulator fast.
  uint32_t color_width = 1280;
  uint32_t color_height = 720;
  CameraStandGeometry stand;
};

// A 65-inch screen, the user seated 0.7 m away, six cameras just outside the screen's corners and
// the centres of its top and bottom edges (the top row aimed at the user's chest and face, the
// bottom row at the waist), the tracker 0.5 m
// from the screen below the right hand facing up at the touch region, the motor on the top-left corner.
SiteDescription make_default_site(const DefaultSiteOptions& options = {});

// Pose of a camera at `position` looking at `target`, image "up" towards +y of the site (OpenCV
// axes: x right, y down, z forward). Throws std::invalid_argument when the points coincide or
// the view is vertical (the roll is undefined then).
Eigen::Isometry3d camera_from_site_looking_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target);
// Pinhole intrinsics with square pixels and the principal point at the image centre.
CameraIntrinsics intrinsics_for_horizontal_fov(uint32_t width, uint32_t height, double horizontal_fov_deg);

struct ShippedSite {
  std::string file_name;  // under assets/sites/
  DefaultSiteOptions options;
};
const std::vector<ShippedSite>& shipped_sites();

}  // namespace rt::sim
