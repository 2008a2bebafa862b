#pragma once
// A simulated session: both sites (each a site description, a user and the user's motion), the
// effects, and how many frames to make. Read from assets/scenes/*.json; site files are named
// relative to the scene file.
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/site_frames.h"
#include "sim/effects.h"
#include "sim/motion.h"
#include "sim/person_mesh.h"
#include "sim/person_pose.h"
#include "sim/site_description.h"

namespace rt::sim {

struct SiteSetup {
  std::filesystem::path site_file;  // as resolved against the scene file's folder
  SiteDescription site;
  UserAppearance user;
  MotionSpec motion;
};

// Where each site takes its user's eye, the viewpoint it sends to the other site: found in its
// cameras (the paper's viewpoint computation: eyes detected, triangulated), or the seat's head
// position from the site description, which a site without a face to find falls back to anyway.
enum class ViewpointSource { Cameras, Seat };

struct Scene {
  std::string name;
  uint32_t frame_count = 1;
  double fps = 30.0;              // RGBD frames; the tracker runs at its own 50 Hz
  double resolution_scale = 1.0;  // of the site's color and depth resolutions
  // Color images and the ground truth rendered at this many times the resolution per axis and
  // box-filtered (odd; 1 = point samples), as a sensor integrates over its pixels.
  uint32_t color_supersampling = 1;
  uint64_t seed = 0;              // every random effect draws from streams derived from it
  ViewpointSource viewpoint = ViewpointSource::Cameras;
  MeshDetail mesh_detail;          // of the simulated users' capsules (the hands' fingers keep a floor)
  std::array<SiteSetup, 2> sites;  // indexed by rt::Site: A, B
  Effects effects;                 // applied at both sites

  const SiteSetup& at(Site site) const { return sites[site == Site::A ? 0 : 1]; }
  double duration_s() const { return frame_count / fps; }
};

// JSON:
// {"name": "clap", "frames": 150, "fps": 30, "resolution_scale": 0.5, "seed": 7,
//  "viewpoint": "cameras" (the default) or "seat",
//  "mesh_detail": {"segments": 16, "rings": 8} (optional; the default),
//  "sites": {"A": {"site": "../sites/default.json",
//                  "cameras": ["top-centre", "bottom-centre"] (optional: only these of the site's),
//                  "user": {"skin_rgb": [r,g,b], "shirt_rgb": [..], "shirt_stripe_rgb": [..],
//                           "stripe_width_m": 0.03, "hand_scale": 1.0},
//                  "motion": {"name": "clap", "touch_target_m": [0.08, 0.05], ...}},
//            "B": {...}},
//  "effects": {"tracker_jitter": {"sigma_mm": 1.5}, ...}}     (optional; empty = no effects)
// The remote viewer's eye that a site's ground truth is seen from, in the remote site's frame:
// the remote user's true eyes when seated upright (sim/face.h) where the scene's sites find the
// eyes in their cameras, else the remote seat's head position, the eye the remote site then sends.
Eigen::Vector3d truth_viewer_eye(const Scene& scene, Site remote);

// Errors start with `where` and name the field; a missing or bad site file is named.
Scene scene_from_json(const nlohmann::json& json, const std::filesystem::path& base_dir, const std::string& where);
Scene load_scene(const std::filesystem::path& path);
// A scene name (assets/scenes/NAME.json, or $REMOTETOUCH_ASSETS/scenes/NAME.json) or a path.
// Throws std::invalid_argument listing the scenes for a name that is none of them.
std::filesystem::path resolve_scene(const std::string& scene);
// The names of the scenes under the assets' scenes/ folder, sorted.
std::vector<std::string> scene_names();

// The motion of `site`'s user, ready to sample: pose_at(frame / scene.fps) for the cameras.
MotionTrack make_motion_track(const Scene& scene, Site site);

UserAppearance appearance_from_json(const nlohmann::json& json, const std::string& where);
nlohmann::json appearance_to_json(const UserAppearance& user);

}  // namespace rt::sim
