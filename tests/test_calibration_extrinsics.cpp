// Extrinsics: cameras linked by simultaneous chessboard views, placed in the site frame by
// their distances to the screen corners (trilateration, then a rigid alignment). Synthetic
// sites with known poses, the opencv-doc stereo pair, and the degenerate inputs.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <tuple>

#include "calibration/calibration_error.h"
#include "calibration/extrinsics_calibration.h"
#include "calibration/intrinsics_calibration.h"
#include "calibration/image_files.h"
#include "calibration/synthetic_site.h"
#include "config/json.h"

using namespace rt;
using namespace rt::calibration;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kOpenCvData = "/usr/share/doc/opencv-doc/examples/data";
constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Exact inputs (no noise at all) leave only the solvers' convergence limits.
constexpr double kExactPositionToleranceM = 1e-6;
constexpr double kExactAngleToleranceRad = 1e-5 * kDegree;
// Corners with 0.1 px noise and exact distances: over 12 shared views the chessboard links
// are good to about 0.1 mm and 0.01 degree (seeds 1 to 8: at most 0.10 mm, 0.012 degree).
constexpr double kCornerNoisePositionToleranceM = 0.5e-3;
constexpr double kCornerNoiseAngleToleranceRad = 0.03 * kDegree;
// Distances measured to 1 mm: a camera 12 cm in front of the screen plane has its depth fixed
// only through the slope of its distances (about 0.1), so its trilaterated position is off by
// up to about 5 mm, and the rigid alignment of six such positions turns the whole rig a little
// (seeds 1 to 8: at most 3.2 mm and 0.31 degree).
constexpr double kMeasuredPositionToleranceM = 10e-3;
constexpr double kMeasuredAngleToleranceRad = 0.5 * kDegree;

std::filesystem::path scratch_folder(const std::string& name) {
  const auto folder = std::filesystem::temp_directory_path() /
                      ("remotetouch-test-calibration-extrinsics-" + std::to_string(getpid())) / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

double angle_between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle();
}

CornerDistances exact_distances(const Eigen::Vector3d& position, const Screen& screen) {
  CornerDistances distances{};
  for (ScreenCorner corner : kScreenCorners)
    distances[size_t(corner)] = (position - corner_position(screen, corner)).norm();
  return distances;
}

void check_poses(const ExtrinsicsResult& result, const sim::SiteDescription& truth, double position_tolerance_m,
                 double angle_tolerance_rad) {
  REQUIRE(result.cameras.size() == truth.cameras.size());
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    const Camera& found = result.cameras[i].camera;
    const Camera expected = truth.cameras[i].color_camera();
    INFO("camera " << truth.cameras[i].name);
    CHECK(found.name == truth.cameras[i].name);
    CHECK(found.camera_from_site.matrix().allFinite());
    CHECK((found.position_in_site() - expected.position_in_site()).norm() < position_tolerance_m);
    CHECK(angle_between(found.camera_from_site, expected.camera_from_site) < angle_tolerance_rad);
    CHECK(found.camera_from_site.linear().determinant() == Approx(1.0).margin(1e-9));
  }
}

// The input with only the named cameras, and the views as those cameras saw them.
ExtrinsicsInput keep_cameras(ExtrinsicsInput input, const std::vector<std::string>& names) {
  auto kept = [&](const std::string& name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  std::erase_if(input.cameras, [&](const CameraSetup& c) { return !kept(c.name); });
  for (BoardSnapshot& snapshot : input.snapshots)
    std::erase_if(snapshot.observations, [&](const CameraObservation& o) { return !kept(o.camera); });
  if (!kept(input.reference_camera)) input.reference_camera = names.front();
  return input;
}

}  // namespace

TEST_CASE("Trilateration from the four screen corners finds the camera", "[calibration][extrinsics]") {
  const Screen screen;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-1.0, 1.0), y(-0.6, 0.6), z(0.0, 0.8);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d position(x(rng), y(rng), z(rng));
    const Trilateration found = trilaterate(exact_distances(position, screen), screen, "camera");
    INFO("at " << position.transpose());
    CHECK((found.position_in_site - position).norm() < kExactPositionToleranceM);
    for (double r : found.residuals_m) CHECK(std::abs(r) < kExactPositionToleranceM);
  }
  // A camera in the screen plane (beside it) has no mirror image to choose from.
  const Eigen::Vector3d beside(0.8, 0.0, 0.0);
  CHECK((trilaterate(exact_distances(beside, screen), screen, "camera").position_in_site - beside).norm() < 1e-5);
  // Corner names go with the seated user's view: +x is the user's right.
  CHECK(corner_position(screen, ScreenCorner::TopRight).x() > 0);
  CHECK(corner_position(screen, ScreenCorner::TopRight).y() > 0);
  CHECK(std::string(corner_name(ScreenCorner::BottomLeft)) == "bottom_left");
}

TEST_CASE("Inconsistent or impossible distances are refused, never a NaN", "[calibration][extrinsics]") {
  const Screen screen;
  const Eigen::Vector3d position(-0.78, 0.46, 0.12);
  CornerDistances distances = exact_distances(position, screen);

  distances[size_t(ScreenCorner::BottomRight)] += 0.15;  // a mis-read tape
  CHECK_THROWS_WITH(trilaterate(distances, screen, "top-left"),
                    Contains("camera 'top-left'") && Contains("inconsistent"));
  // No point is 10 cm from all four corners of a 1.4 m screen.
  CHECK_THROWS_WITH(trilaterate({0.1, 0.1, 0.1, 0.1}, screen, "c"), Contains("inconsistent"));
  CHECK_THROWS_WITH(trilaterate({0.5, -0.5, 0.5, 0.5}, screen, "c"), Contains("positive number of metres"));
  CHECK_THROWS_WITH(trilaterate({0.5, std::nan(""), 0.5, 0.5}, screen, "c"), Contains("top_right"));
  // Within the stated limit, the small error is reported, not refused.
  distances = exact_distances(position, screen);
  distances[size_t(ScreenCorner::TopLeft)] += 0.004;
  const Trilateration found = trilaterate(distances, screen, "top-left");
  CHECK(found.position_in_site.allFinite());
  CHECK(std::abs(found.residuals_m[0]) > 0.0);
}

TEST_CASE("Exact views and distances give the site's cameras back exactly", "[calibration][extrinsics]") {
  SyntheticSiteOptions options;
  options.corner_noise_px = 0.0;
  options.distance_noise_mm = 0.0;
  const SyntheticSite site = make_synthetic_site(options);
  const ExtrinsicsResult result = calibrate_extrinsics(site.extrinsics_input);
  check_poses(result, site.truth, kExactPositionToleranceM, kExactAngleToleranceRad);
  for (const PlacedCamera& placed : result.cameras) CHECK(placed.link.rms_error_px < 1e-3);
}

TEST_CASE("Noisy corners and measured distances: poses within the stated tolerances", "[calibration][extrinsics]") {
  SECTION("0.1 px corner noise, exact distances") {
    SyntheticSiteOptions options;
    options.distance_noise_mm = 0.0;
    const SyntheticSite site = make_synthetic_site(options);
    const ExtrinsicsResult result = calibrate_extrinsics(site.extrinsics_input);
    check_poses(result, site.truth, kCornerNoisePositionToleranceM, kCornerNoiseAngleToleranceRad);
    for (const PlacedCamera& placed : result.cameras) {
      CHECK(placed.link.rms_error_px < 0.2);  // the noise's own RMS is 0.14 px per corner
      CHECK((placed.link.linked_to.empty()) == (placed.camera.name == site.extrinsics_input.reference_camera));
    }
  }
  SECTION("0.1 px corner noise, distances to 1 mm") {
    for (uint32_t seed = 1; seed <= 3; ++seed) {
      SyntheticSiteOptions options;
      options.seed = seed;
      const SyntheticSite site = make_synthetic_site(options);
      const ExtrinsicsResult result = calibrate_extrinsics(site.extrinsics_input);
      check_poses(result, site.truth, kMeasuredPositionToleranceM, kMeasuredAngleToleranceRad);
      CHECK(result.alignment_rms_m < 5e-3);
    }
  }
}

TEST_CASE("The chessboard links chain relative poses through the best-connected camera", "[calibration][extrinsics]") {
  SyntheticSiteOptions options;
  options.corner_noise_px = 0.0;
  const SyntheticSite site = make_synthetic_site(options);
  std::vector<NamedIntrinsics> cameras;
  for (const sim::RgbdCamera& camera : site.truth.cameras) cameras.push_back({camera.name, camera.color});
  const size_t n = cameras.size();
  auto index_of = [&](const std::string& name) {
    for (size_t i = 0; i < n; ++i)
      if (cameras[i].name == name) return i;
    FAIL("no camera named '" << name << "'");
    return n;
  };
  // The views each pair of cameras shares, counted here from the snapshots.
  std::vector<std::vector<size_t>> shared(n, std::vector<size_t>(n, 0));
  for (const BoardSnapshot& snapshot : site.extrinsics_input.snapshots)
    for (const CameraObservation& a : snapshot.observations)
      for (const CameraObservation& b : snapshot.observations)
        if (a.camera != b.camera) ++shared[index_of(a.camera)][index_of(b.camera)];
  // The best a tree of links can do: a maximum spanning tree's total of shared views (Kruskal).
  size_t best_total = 0;
  {
    std::vector<std::tuple<size_t, size_t, size_t>> edges;
    for (size_t a = 0; a < n; ++a)
      for (size_t b = a + 1; b < n; ++b)
        if (shared[a][b] > 0) edges.emplace_back(shared[a][b], a, b);
    std::sort(edges.rbegin(), edges.rend());
    std::vector<size_t> group(n);
    for (size_t i = 0; i < n; ++i) group[i] = i;
    auto root = [&](size_t i) {
      while (group[i] != i) i = group[i];
      return i;
    };
    for (const auto& [count, a, b] : edges)
      if (root(a) != root(b)) {
        group[root(a)] = root(b);
        best_total += count;
      }
  }

  size_t unique_best_pairs_checked = 0;
  // The first camera, and the input's own reference (which is not the first).
  for (const std::string reference : {"top-left", "top-centre"}) {
    INFO("reference camera " << reference);
    const size_t r = index_of(reference);
    const auto links = link_cameras(cameras, site.extrinsics_input.snapshots, site.extrinsics_input.board, reference);
    REQUIRE(links.size() == n);
    const Eigen::Isometry3d reference_from_site = site.truth.cameras[r].camera_from_site;
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
      INFO("camera " << cameras[i].name << ", linked to '" << links[i].linked_to << "'");
      CHECK(links[i].camera == cameras[i].name);
      const Eigen::Isometry3d expected = site.truth.cameras[i].camera_from_site * reference_from_site.inverse();
      CHECK((links[i].camera_from_reference.translation() - expected.translation()).norm() < 1e-6);
      CHECK(angle_between(links[i].camera_from_reference, expected) < 1e-6);
      if (i == r) {
        CHECK(links[i].linked_to.empty());
        CHECK(links[i].shared_views == 0);
        continue;
      }
      // Linked through a camera it shares views with, the count given is theirs, and the chain
      // of links reaches the reference.
      const size_t parent = index_of(links[i].linked_to);
      CHECK(links[i].shared_views == shared[i][parent]);
      CHECK(links[i].shared_views > 0);
      size_t at = i, steps = 0;
      while (at != r && steps++ < n) at = index_of(links[at].linked_to);
      CHECK(at == r);
      total += links[i].shared_views;
    }
    // The links form a tree with the most shared views there can be: each camera joined through
    // the linked camera it saw the board with most often. Linking every camera to the reference,
    // or to the first camera, would share fewer views in this site (checked here, so that the
    // test keeps telling them apart).
    CHECK(total == best_total);
    size_t star_total = 0;
    for (size_t i = 0; i < n; ++i) star_total += shared[i][r];
    CHECK(star_total < best_total);
    // A camera and the one camera it shares the most views with are linked, one way or the
    // other (such a pair is in every maximum spanning tree).
    for (size_t i = 0; i < n; ++i) {
      const size_t most = *std::max_element(shared[i].begin(), shared[i].end());
      if (std::count(shared[i].begin(), shared[i].end(), most) != 1) continue;
      const size_t j = size_t(std::max_element(shared[i].begin(), shared[i].end()) - shared[i].begin());
      INFO(cameras[i].name << " shares the most views (" << most << ") with " << cameras[j].name);
      CHECK((links[i].linked_to == cameras[j].name || links[j].linked_to == cameras[i].name));
      ++unique_best_pairs_checked;
    }
  }
  CHECK(unique_best_pairs_checked > 0);
  CHECK(best_total > 0);
  CHECK_THROWS_WITH(link_cameras(cameras, site.extrinsics_input.snapshots, site.extrinsics_input.board, "nobody"),
                    Contains("reference camera 'nobody'"));
}

TEST_CASE("Degenerate camera sets give a clear error", "[calibration][extrinsics]") {
  const SyntheticSite site = make_synthetic_site();
  const ExtrinsicsInput& full = site.extrinsics_input;

  SECTION("three cameras on one line (the top edge)") {
    const ExtrinsicsInput line = keep_cameras(full, {"top-left", "top-centre", "top-right"});
    CHECK_THROWS_WITH(calibrate_extrinsics(line), Contains("lie on a line"));
  }
  SECTION("three cameras off a line are enough") {
    const ExtrinsicsInput three = keep_cameras(full, {"top-left", "top-centre", "bottom-right"});
    const ExtrinsicsResult result = calibrate_extrinsics(three);
    CHECK(result.cameras.size() == 3);
  }
  SECTION("fewer than three cameras") {
    CHECK_THROWS_WITH(calibrate_extrinsics(keep_cameras(full, {"top-left", "bottom-left"})),
                      Contains("at least 3 cameras"));
  }
  SECTION("a camera that shares no view") {
    ExtrinsicsInput input = full;
    for (BoardSnapshot& snapshot : input.snapshots)
      std::erase_if(snapshot.observations, [](const CameraObservation& o) { return o.camera == "bottom-right"; });
    CHECK_THROWS_WITH(calibrate_extrinsics(input), Contains("'bottom-right' share no chessboard view"));
  }
  SECTION("corner distances named as seen from behind the screen (left and right swapped)") {
    ExtrinsicsInput input = full;
    for (CameraSetup& camera : input.cameras) {
      auto& d = camera.corner_distances_m;
      std::swap(d[size_t(ScreenCorner::TopLeft)], d[size_t(ScreenCorner::TopRight)]);
      std::swap(d[size_t(ScreenCorner::BottomLeft)], d[size_t(ScreenCorner::BottomRight)]);
    }
    CHECK_THROWS_WITH(calibrate_extrinsics(input), Contains("look away from the user"));
  }
  SECTION("one camera's distances do not fit the chessboard poses") {
    ExtrinsicsInput input = full;
    // Consistent among themselves, but for a point 10 cm further up.
    const Eigen::Vector3d moved = site.truth.cameras[1].color_camera().position_in_site() + Eigen::Vector3d(0, 0.1, 0);
    input.cameras[1].corner_distances_m = exact_distances(moved, input.screen);
    CHECK_THROWS_WITH(calibrate_extrinsics(input), Contains("disagree"));
  }
  SECTION("views that disagree (a camera's corners numbered from the other end)") {
    ExtrinsicsInput input = full;
    for (BoardSnapshot& snapshot : input.snapshots)
      for (CameraObservation& observation : snapshot.observations)
        if (observation.camera == "top-right") std::reverse(observation.corners.begin(), observation.corners.end());
    CHECK_THROWS_WITH(calibrate_extrinsics(input), Contains("top-right") && Contains("disagree"));
  }
}

TEST_CASE("The extrinsics input file: paths, intrinsics files and errors that name the field",
          "[calibration][extrinsics]") {
  const SyntheticSite site = make_synthetic_site();
  const auto folder = scratch_folder("input");
  write_synthetic_site(site, folder);
  const ExtrinsicsInput input = read_extrinsics_input(folder / "extrinsics_input.json");
  REQUIRE(input.cameras.size() == 6);
  CHECK(input.cameras[2].intrinsics.fx == site.truth.cameras[2].color.fx);
  CHECK(input.snapshots.size() == site.extrinsics_input.snapshots.size());
  const ExtrinsicsResult from_file = calibrate_extrinsics(input);
  const ExtrinsicsResult in_memory = calibrate_extrinsics(site.extrinsics_input);
  for (size_t i = 0; i < 6; ++i)
    CHECK((from_file.cameras[i].camera.position_in_site() - in_memory.cameras[i].camera.position_in_site()).norm() <
          1e-5);  // corners are written as floats

  nlohmann::json json = config::read_json_file(folder / "extrinsics_input.json");
  auto fails_with = [&](nlohmann::json broken, const std::string& message) {
    CHECK_THROWS_WITH(extrinsics_input_from_json(broken, folder, "input"), Contains(message));
  };
  {
    nlohmann::json broken = json;
    broken["cameras"][1]["screen_corner_distances_m"].erase("bottom_left");
    fails_with(broken, "camera 'top-centre' screen_corner_distances_m: missing the distance to 'bottom_left'");
  }
  {
    nlohmann::json broken = json;
    broken["cameras"][0]["screen_corner_distances_m"]["middle"] = 0.5;
    fails_with(broken, "unknown corner 'middle'");
  }
  {
    nlohmann::json broken = json;
    broken["cameras"][0]["intrinsics"] = "intrinsics/missing.json";
    fails_with(broken, "missing.json");
  }
  {
    nlohmann::json broken = json;
    broken["board"]["inner_corners"] = "8x6";
    fails_with(broken, "half-turn");
  }
  {
    nlohmann::json broken = json;
    broken["views"][0]["cameras"]["nobody"] = {{"corners_px", nlohmann::json::array()}};
    fails_with(broken, "camera 'nobody': no such camera");
  }
  {
    nlohmann::json broken = json;
    broken["views"][0]["cameras"]["top-left"] = {{"image", (kOpenCvData / "left01.jpg").string()}};
    fails_with(broken, "is 640x480, the camera's intrinsics are for 1280x720");
  }
  {
    nlohmann::json broken = json;
    broken["views"][0]["cameras"]["top-left"] = {{"corners_px", {{1.0, 2.0}, {3.0}}}};
    fails_with(broken, "corner 1 must be [x, y]");
  }
}

TEST_CASE("The opencv-doc stereo pair, read as an extrinsics input with images: the right camera sits beside the left",
          "[calibration][extrinsics][photographs]") {
  INFO("needs Debian's opencv-doc in " << kOpenCvData);
  REQUIRE(std::filesystem::exists(kOpenCvData / "right01.jpg"));
  const Chessboard board = parse_chessboard("9x6", 0.025);
  nlohmann::json json;
  json["board"] = {{"inner_corners", "9x6"}, {"square_m", 0.025}};
  for (const char* side : {"left", "right"}) {
    const auto images = expand_image_patterns({(kOpenCvData / (std::string(side) + "[0-9]*.jpg")).string()});
    const CameraIntrinsics intrinsics = calibrate_intrinsics_from_images(images, board).result.intrinsics;
    // A stereo pair has no screen: these distances only satisfy the format.
    json["cameras"].push_back({{"name", side},
                               {"intrinsics", intrinsics_to_json(intrinsics)},
                               {"screen_corner_distances_m",
                                {{"top_left", 1.0}, {"top_right", 1.0}, {"bottom_right", 1.0}, {"bottom_left", 1.0}}}});
  }
  for (const auto& left : expand_image_patterns({(kOpenCvData / "left[0-9]*.jpg").string()})) {
    const std::string number = left.filename().string().substr(4);
    json["views"].push_back({{"name", number},
                             {"cameras",
                              {{"left", {{"image", left.string()}}},
                               {"right", {{"image", (kOpenCvData / ("right" + number)).string()}}}}}});
  }
  const ExtrinsicsInput input = extrinsics_input_from_json(json, kOpenCvData, "stereo pair");
  CHECK(input.board_not_found.empty());
  REQUIRE(input.snapshots.size() == 13);
  std::vector<NamedIntrinsics> cameras;
  for (const CameraSetup& camera : input.cameras) cameras.push_back({camera.name, camera.intrinsics});
  const auto links = link_cameras(cameras, input.snapshots, board, "left");
  const CameraLink& right = links[1];
  const Eigen::Vector3d baseline = right.camera_from_reference.inverse().translation();  // right's centre, left's frame
  INFO("right camera centre in the left camera's frame " << baseline.transpose() << " m, turned "
                                                         << angle_between(right.camera_from_reference,
                                                                          Eigen::Isometry3d::Identity()) / kDegree
                                                         << " degrees, link RMS " << right.rms_error_px << " px");
  CHECK(right.shared_views == 13);
  // A horizontal stereo rig: the right camera is to the right (+x), hardly above or ahead, and
  // looks almost the same way; the views agree to a fraction of a pixel.
  CHECK(baseline.x() > 0.0);
  CHECK(std::abs(baseline.y()) < 0.1 * baseline.norm());
  CHECK(std::abs(baseline.z()) < 0.1 * baseline.norm());
  CHECK(angle_between(right.camera_from_reference, Eigen::Isometry3d::Identity()) < 5 * kDegree);
  CHECK(right.rms_error_px < 0.5);

  // Two cameras cannot be placed in the site frame: the alignment needs three.
  CHECK_THROWS_WITH(calibrate_extrinsics(input), Contains("at least 3 cameras"));
}
