#include "calibration/synthetic_site.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "calibration/calibration_error.h"
#include "config/json.h"
#include "sim/default_site.h"

namespace rt::calibration {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The default site's stand, held farther out: the distances to the screen corners fix a camera's
// depth only through their slope, about in_front / distance, so a camera 3 cm in front of the
// glass would have its depth known to a few centimetres from 1 mm tape readings; 12 cm gives
// about 5 mm (see the tolerances in tests/test_calibration_extrinsics.cpp).
constexpr sim::CameraStandGeometry kCalibrationStand{0.06, 0.12};
// A camera must see the whole board at least this far inside the image, and no more obliquely
// than this, for the corner finder to find it.
constexpr double kImageMarginPx = 20.0;
constexpr double kMaxViewAngleRad = 70.0 * kPi / 180.0;
constexpr size_t kMinViewsPerCamera = 4;
// The touches: a grid over the part of the glass the default site's tracker sees.
constexpr int kTouchColumns = 5, kTouchRows = 4;
const Eigen::Vector2d kTouchGridMin(-0.2, -0.3), kTouchGridMax(0.5, 0.15);

CameraIntrinsics kinect_like_intrinsics(size_t index) {
  // 1280x720 color, about 92 degrees across, mild barrel distortion; each unit a little off.
  CameraIntrinsics k;
  k.width = 1280;
  k.height = 720;
  k.fx = 612.0 + 3.0 * double(index);
  k.fy = k.fx + 0.4;
  k.cx = 638.0 + 1.5 * double(index);
  k.cy = 362.0 - 1.0 * double(index);
  k.distortion.k1 = 0.07 + 0.004 * double(index);
  k.distortion.k2 = -0.09;
  k.distortion.p1 = 0.0004;
  k.distortion.p2 = -0.0003;
  k.distortion.k3 = 0.03;
  return k;
}

// `held_at`: where the board's centre is held on average.
Eigen::Isometry3d site_from_board_pose(std::mt19937& rng, const Chessboard& board, const Eigen::Vector3d& held_at) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  // Held up facing the screen: board x along site -x and y along site -y, as the cameras
  // (image x to the user's left) see it unrotated; then tilted a little every way.
  Eigen::Matrix3d facing_screen;
  facing_screen << -1, 0, 0, 0, -1, 0, 0, 0, 1;
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.35 * unit(rng), Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(0.45 * unit(rng), Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(0.3 * unit(rng), Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const Eigen::Vector3d centre = held_at + Eigen::Vector3d(0.12 * unit(rng), 0.06 * unit(rng), 0.06 * unit(rng));
  const Eigen::Vector3d board_centre((board.cols - 1) * board.square_m / 2, (board.rows - 1) * board.square_m / 2, 0);
  Eigen::Isometry3d site_from_board = Eigen::Isometry3d::Identity();
  site_from_board.linear() = tilt * facing_screen;
  site_from_board.translation() = centre - site_from_board.linear() * board_centre;
  return site_from_board;
}

// The corners as `camera` would find them, or nothing when it does not see the whole board.
std::optional<std::vector<cv::Point2f>> observe(const Camera& camera, const Eigen::Isometry3d& site_from_board,
                                                const Chessboard& board, double noise_px, std::mt19937& rng) {
  const Eigen::Vector3d normal = site_from_board.linear().col(2);  // points away from the printed face
  const Eigen::Vector3d to_camera = (camera.position_in_site() - site_from_board.translation()).normalized();
  if (!(-normal.dot(to_camera) > std::cos(kMaxViewAngleRad))) return std::nullopt;
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<cv::Point2f> corners;
  for (const cv::Point3f& corner : board.object_points()) {
    const Eigen::Vector3d site_point = site_from_board * Eigen::Vector3d(corner.x, corner.y, corner.z);
    // Far outside the field of view the distortion polynomial folds back into the image.
    const Eigen::Vector3d in_camera = camera.camera_from_site * site_point;
    if (!(in_camera.z() > 0.1) || std::abs(in_camera.x() / in_camera.z()) > 1.2 ||
        std::abs(in_camera.y() / in_camera.z()) > 0.8)
      return std::nullopt;
    const auto pixel = camera.project(site_point);
    if (!pixel || pixel->x() < kImageMarginPx || pixel->y() < kImageMarginPx ||
        pixel->x() > camera.intrinsics.width - kImageMarginPx || pixel->y() > camera.intrinsics.height - kImageMarginPx)
      return std::nullopt;
    corners.emplace_back(float(pixel->x() + noise(rng)), float(pixel->y() + noise(rng)));
  }
  return corners;
}

void add_board_views(SyntheticSite& site, const SyntheticSiteOptions& options, std::mt19937& rng) {
  ExtrinsicsInput& input = site.extrinsics_input;
  std::vector<size_t> views_per_camera(site.truth.cameras.size(), 0);
  std::vector<Camera> cameras;
  for (const sim::RgbdCamera& camera : site.truth.cameras) cameras.push_back(camera.color_camera());
  for (size_t attempt = 0; input.snapshots.size() < options.board_poses && attempt < 200 * options.board_poses;
       ++attempt) {
    // The board is held in front of each camera in turn, on its axis 0.4 to 0.64 m from the glass,
    // where the cameras of its row (which look at one point) see it too.
    const Camera& facing = cameras[input.snapshots.size() % cameras.size()];
    const Eigen::Vector3d mount = facing.position_in_site();
    const Eigen::Vector3d axis = facing.camera_from_site.inverse().linear().col(2);
    const double held_z = 0.52 + 0.12 * std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
    const Eigen::Vector3d held_at = mount + axis * ((held_z - mount.z()) / axis.z());
    const Eigen::Isometry3d site_from_board = site_from_board_pose(rng, input.board, held_at);
    BoardSnapshot snapshot;
    snapshot.name = "view-" + std::to_string(input.snapshots.size());
    for (size_t c = 0; c < site.truth.cameras.size(); ++c)
      if (auto corners = observe(cameras[c], site_from_board, input.board, options.corner_noise_px, rng)) {
        snapshot.observations.push_back({site.truth.cameras[c].name, std::move(*corners)});
        ++views_per_camera[c];
      }
    if (snapshot.observations.size() >= 2) {
      input.snapshots.push_back(std::move(snapshot));
      site.site_from_board.push_back(site_from_board);
    }
  }
  for (size_t c = 0; c < views_per_camera.size(); ++c)
    if (views_per_camera[c] < std::min(kMinViewsPerCamera, options.board_poses))
      throw CalibrationError("synthetic site: camera '" + site.truth.cameras[c].name + "' saw the board only " +
                             std::to_string(views_per_camera[c]) + " times; ask for more board poses");
}

void add_touches(SyntheticSite& site, const SyntheticSiteOptions& options, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, options.tip_noise_mm);
  const sim::TrackerPlacement& tracker = site.truth.tracker;
  const Eigen::Vector2d step =
      (kTouchGridMax - kTouchGridMin).cwiseQuotient(Eigen::Vector2d(kTouchColumns - 1, kTouchRows - 1));
  for (int r = 0; r < kTouchRows; ++r)
    for (int c = 0; c < kTouchColumns; ++c) {
      TrackerTouch touch;
      char label[32];
      std::snprintf(label, sizeof label, "row%d-col%d", r, c);
      touch.label = label;
      touch.site_m = {kTouchGridMin.x() + step.x() * c, kTouchGridMax.y() - step.y() * r, 0.0};
      if (!tracker.sees(touch.site_m))
        throw CalibrationError("synthetic site: the tracker does not see the touch '" + touch.label + "'");
      touch.tip_mm =
          (tracker.tracker_from_site() * touch.site_m) * 1000.0 + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      site.touches.push_back(touch);
    }
  site.touch_is_outlier.assign(site.touches.size(), false);
  std::vector<size_t> order(site.touches.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), slip_mm(30.0, 60.0);
  for (size_t i = 0; i < std::min(options.tip_outliers, order.size()); ++i) {
    const Eigen::Vector3d direction = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    site.touches[order[i]].tip_mm += direction * slip_mm(rng);
    site.touch_is_outlier[order[i]] = true;
  }
}

}  // namespace

SyntheticSite make_synthetic_site(const SyntheticSiteOptions& options) {
  std::mt19937 rng(options.seed);
  SyntheticSite site;
  sim::DefaultSiteOptions site_options;
  site_options.name = "synthetic";
  site_options.stand = kCalibrationStand;
  site.truth = sim::make_default_site(site_options);
  // Real lenses: each unit a little off the nominal, with distortion. The site file keeps it
  // (the simulator refuses to render such a site; calibration does not need it rendered).
  for (size_t index = 0; index < site.truth.cameras.size(); ++index)
    site.truth.cameras[index].color = kinect_like_intrinsics(index);

  ExtrinsicsInput& input = site.extrinsics_input;
  input.board = parse_chessboard("9x6", 0.05);
  input.screen = site.truth.screen;
  std::normal_distribution<double> distance_noise(0.0, options.distance_noise_mm * 1e-3);
  for (const sim::RgbdCamera& camera : site.truth.cameras) {
    CameraSetup setup;
    setup.name = camera.name;
    setup.intrinsics = camera.color;
    const Eigen::Vector3d position = camera.camera_from_site.inverse().translation();
    for (ScreenCorner corner : kScreenCorners)
      setup.corner_distances_m[size_t(corner)] =
          (position - corner_position(input.screen, corner)).norm() + distance_noise(rng);
    input.cameras.push_back(setup);
  }
  input.reference_camera = "top-centre";
  add_board_views(site, options, rng);
  add_touches(site, options, rng);
  return site;
}

void write_synthetic_site(const SyntheticSite& site, const std::filesystem::path& folder) {
  nlohmann::json input = extrinsics_input_to_json(site.extrinsics_input);
  for (nlohmann::json& camera : input["cameras"]) {
    const std::string file = "intrinsics/" + camera["name"].get<std::string>() + ".json";
    config::write_json_file(folder / file, camera["intrinsics"]);
    camera["intrinsics"] = file;
  }
  config::write_json_file(folder / "extrinsics_input.json", input);
  config::write_json_file(folder / "tracker_touches.json", tracker_touches_to_json(site.touches));
  sim::write_site(folder / "truth_site.json", site.truth);
  nlohmann::json outliers = nlohmann::json::array();
  for (size_t i = 0; i < site.touches.size(); ++i)
    if (site.touch_is_outlier[i]) outliers.push_back(site.touches[i].label);
  config::write_json_file(folder / "truth_touch_outliers.json", {{"outliers", outliers}});
}

}  // namespace rt::calibration
