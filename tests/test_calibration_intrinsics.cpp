// Intrinsics (Zhang's method through OpenCV): synthetic views with known intrinsics, rendered
// chessboard photographs, the real opencv-doc photographs against OpenCV's reference file, and
// the errors for bad input.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "calibration/calibration_error.h"
#include "calibration/image_files.h"
#include "calibration/intrinsics_calibration.h"
#include "calibration/synthetic_board_image.h"

using namespace rt;
using namespace rt::calibration;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kOpenCvDataCalibrationIntrinsics = "/usr/share/doc/opencv-doc/examples/data";

// Synthetic corners with 0.1 px noise, 15 views of a 1280x720 camera: OpenCV puts the
// standard deviation of fx, fy, cx, cy at about 1 px for such a set, and over ten seeds the
// errors stay below 1.2 px; 3 px is three standard deviations.
constexpr double kCornerNoisePx = 0.1;
constexpr double kFocalTolerancePx = 3.0;
constexpr double kPrincipalPointTolerancePx = 3.0;
// Distortion coefficients trade off against each other (k2 against k3) and against the
// principal point; what must match is how the lens bends rays where the boards were (the
// central 80 % of the image; beyond, the polynomial is extrapolated). Over ten seeds the
// mismatch stays below 0.42 px, where the distortion itself moves pixels by about 50 px.
constexpr double kDistortionTolerancePx = 0.8;
constexpr double kCoveredFraction = 0.8;

// Rendered photographs: the renderer's anti-aliasing and the corner finder together leave
// corners about 0.1 px off, with a small bias, so the bounds are wider.
constexpr double kRenderedCornerTolerancePx = 0.25;
constexpr double kRenderedFocalToleranceRelative = 0.005;
constexpr double kRenderedPrincipalPointTolerancePx = 3.0;

// The opencv-doc photographs. OpenCV's reference run reports 0.39 px RMS (its fixed 11 px
// corner-refinement window reaches neighbouring corners on these 30 px squares); a window that
// stays inside a square gives about 0.18 px. Bound: a clear margin above that, still below
// the reference.
constexpr double kPhotoMaxRmsPx = 0.3;
// Two calibrations of one camera from one photo set, with different corner refinements,
// agree about this well: focal length within 1 %, principal point within 5 px (1 % of the
// width), and distortion within 2 px over the central 80 % of the image (0.9 px measured;
// the reference's own distortion moves pixels there by up to 57 px).
constexpr double kPhotoFocalToleranceRelative = 0.01;
constexpr double kPhotoPrincipalPointTolerancePx = 5.0;
constexpr double kPhotoDistortionTolerancePx = 2.0;

std::filesystem::path scratch_folder_calibration_intrinsics(const std::string& name) {
  const auto folder = std::filesystem::temp_directory_path() /
                      ("remotetouch-test-calibration-intrinsics-" + std::to_string(getpid())) / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

cv::Matx33d camera_matrix(const CameraIntrinsics& k) { return {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}; }

cv::Mat distortion_of(const CameraIntrinsics& k) {
  const auto c = k.distortion.as_opencv();
  return cv::Mat(1, 8, CV_64F, const_cast<double*>(c.data())).clone();
}

// How differently two cameras bend rays, leaving aside focal length and principal point: the
// pixels within `fraction` of the half-size around the image centre are undistorted with each
// camera, the best affine map takes one set of normalised points onto the other (absorbing
// fx, fy, cx, cy), and the largest remaining mismatch is returned in pixels of `b`.
double distortion_mismatch_px(const CameraIntrinsics& a, const CameraIntrinsics& b, double fraction) {
  std::vector<cv::Point2f> pixels;
  const double half_w = a.width / 2.0, half_h = a.height / 2.0;
  for (int v = 0; v <= int(a.height); v += 10)
    for (int u = 0; u <= int(a.width); u += 10)
      if (std::abs(u - half_w) <= fraction * half_w && std::abs(v - half_h) <= fraction * half_h)
        pixels.emplace_back(float(u), float(v));
  std::vector<cv::Point2f> in_a, in_b;
  cv::undistortPoints(pixels, in_a, camera_matrix(a), distortion_of(a));
  cv::undistortPoints(pixels, in_b, camera_matrix(b), distortion_of(b));
  Eigen::MatrixXd design(pixels.size(), 3);
  Eigen::MatrixXd target(pixels.size(), 2);
  for (size_t i = 0; i < pixels.size(); ++i) {
    design.row(Eigen::Index(i)) << in_a[i].x, in_a[i].y, 1.0;
    target.row(Eigen::Index(i)) << in_b[i].x, in_b[i].y;
  }
  const Eigen::MatrixXd affine = design.colPivHouseholderQr().solve(target);
  const Eigen::MatrixXd mismatch = design * affine - target;
  return mismatch.rowwise().norm().maxCoeff() * b.fx;
}

CameraIntrinsics test_camera() {
  CameraIntrinsics k;
  k.width = 1280;
  k.height = 720;
  k.fx = 915.0;
  k.fy = 912.0;
  k.cx = 645.0;
  k.cy = 355.0;
  k.distortion.k1 = -0.12;
  k.distortion.k2 = 0.09;
  k.distortion.p1 = 0.0008;
  k.distortion.p2 = -0.0005;
  k.distortion.k3 = -0.02;
  return k;
}

// Board poses that put the board all over the image, tilted up to about 35 degrees.
Eigen::Isometry3d board_pose(std::mt19937& rng, const Chessboard& board, double distance_m, double spread_m) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::Isometry3d camera_from_board = Eigen::Isometry3d::Identity();
  camera_from_board.linear() = (Eigen::AngleAxisd(0.6 * unit(rng), Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(0.6 * unit(rng), Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(0.4 * unit(rng), Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const Eigen::Vector3d centre((board.cols - 1) * board.square_m / 2, (board.rows - 1) * board.square_m / 2, 0);
  const Eigen::Vector3d where(spread_m * unit(rng), 0.6 * spread_m * unit(rng), distance_m * (1.0 + 0.15 * unit(rng)));
  camera_from_board.translation() = where - camera_from_board.linear() * centre;
  return camera_from_board;
}

// The board's corners as the camera sees them; empty when a corner falls outside the image.
std::vector<cv::Point2f> project_board(const CameraIntrinsics& k, const Eigen::Isometry3d& camera_from_board,
                                       const Chessboard& board) {
  cv::Matx33d rotation;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation(r, c) = camera_from_board.linear()(r, c);
  cv::Vec3d rotation_vector;
  cv::Rodrigues(rotation, rotation_vector);
  const Eigen::Vector3d t = camera_from_board.translation();
  std::vector<cv::Point2f> corners;
  cv::projectPoints(board.object_points(), rotation_vector, cv::Vec3d(t.x(), t.y(), t.z()), camera_matrix(k),
                    distortion_of(k), corners);
  for (const auto& c : corners)
    if (c.x < 5 || c.y < 5 || c.x > k.width - 5.0f || c.y > k.height - 5.0f) return {};
  return corners;
}

CameraIntrinsics reference_left_intrinsics() {
  cv::FileStorage file((kOpenCvDataCalibrationIntrinsics / "left_intrinsics.yml").string(), cv::FileStorage::READ);
  REQUIRE(file.isOpened());
  cv::Mat matrix, distortion;
  file["camera_matrix"] >> matrix;
  file["distortion_coefficients"] >> distortion;
  CameraIntrinsics k;
  k.width = uint32_t(int(file["image_width"]));
  k.height = uint32_t(int(file["image_height"]));
  k.fx = matrix.at<double>(0, 0);
  k.fy = matrix.at<double>(1, 1);
  k.cx = matrix.at<double>(0, 2);
  k.cy = matrix.at<double>(1, 2);
  k.distortion = Distortion::from_opencv(distortion.ptr<double>(), distortion.total());
  return k;
}

}  // namespace

TEST_CASE("A board is given as inner corners COLSxROWS and a square size in metres", "[calibration][intrinsics]") {
  const Chessboard board = parse_chessboard("9x6", 0.025);
  CHECK(board.cols == 9);
  CHECK(board.rows == 6);
  CHECK(board.corner_count() == 54);
  CHECK(board.object_points()[10] == cv::Point3f(0.025f, 0.025f, 0.0f));
  CHECK(parse_chessboard(" 7X4 ", 0.03).rows == 4);
  CHECK_FALSE(board.same_after_half_turn());
  CHECK(parse_chessboard("8x6", 0.03).same_after_half_turn());

  for (const char* bad : {"9by6", "9x", "x6", "", "9x6x2", "-9x6", "9.5x6"})
    CHECK_THROWS_WITH(parse_chessboard(bad, 0.025), Contains("expected COLSxROWS"));
  CHECK_THROWS_WITH(parse_chessboard("2x6", 0.025), Contains("inner corners"));
  CHECK_THROWS_WITH(parse_chessboard("9x600", 0.025), Contains("inner corners"));
  CHECK_THROWS_WITH(parse_chessboard("9x6", 0.0), Contains("positive number of metres"));
  CHECK_THROWS_WITH(parse_chessboard("9x6", std::nan("")), Contains("positive number of metres"));
  CHECK_THROWS_WITH(parse_chessboard("9x6", 25.0), Contains("in metres"));
}

TEST_CASE("Synthetic views with 0.1 px noise give back the camera", "[calibration][intrinsics]") {
  const CameraIntrinsics truth = test_camera();
  const Chessboard board = parse_chessboard("9x6", 0.04);
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, float(kCornerNoisePx));
  std::vector<BoardView> views;
  while (views.size() < 15) {
    auto corners = project_board(truth, board_pose(rng, board, 0.75, 0.32), board);
    if (corners.empty()) continue;
    for (auto& c : corners) c += cv::Point2f(noise(rng), noise(rng));
    views.push_back({"view " + std::to_string(views.size()), corners});
  }

  const IntrinsicsResult result = calibrate_intrinsics(views, board, cv::Size(1280, 720));
  const CameraIntrinsics& found = result.intrinsics;
  INFO("found " << intrinsics_to_json(found).dump() << ", distortion mismatch "
                << distortion_mismatch_px(found, truth, kCoveredFraction) << " px");
  CHECK(found.width == 1280);
  CHECK(found.height == 720);
  CHECK(found.fx == Approx(truth.fx).margin(kFocalTolerancePx));
  CHECK(found.fy == Approx(truth.fy).margin(kFocalTolerancePx));
  CHECK(found.cx == Approx(truth.cx).margin(kPrincipalPointTolerancePx));
  CHECK(found.cy == Approx(truth.cy).margin(kPrincipalPointTolerancePx));
  CHECK(distortion_mismatch_px(found, truth, kCoveredFraction) < kDistortionTolerancePx);
  for (double deviation : {result.std_dev_px.fx, result.std_dev_px.fy, result.std_dev_px.cx, result.std_dev_px.cy}) {
    CHECK(deviation > 0.0);
    CHECK(deviation < kFocalTolerancePx);
  }
  // The fit leaves the noise: its RMS is the noise's RMS per point (sqrt(2) * 0.1 px) less
  // what the parameters absorb.
  CHECK(result.rms_error_px > 0.8 * kCornerNoisePx);
  CHECK(result.rms_error_px < 1.6 * kCornerNoisePx);
  REQUIRE(result.view_rms_error_px.size() == views.size());
  for (double e : result.view_rms_error_px) CHECK(e < 3 * kCornerNoisePx);
}

TEST_CASE("Square pixels and the rational model are options of the fit", "[calibration][intrinsics]") {
  CameraIntrinsics truth = test_camera();
  truth.fy = truth.fx;
  truth.distortion.k4 = 0.05;
  const Chessboard board = parse_chessboard("9x6", 0.04);
  std::mt19937 rng(6);
  std::vector<BoardView> views;
  while (views.size() < 15) {
    auto corners = project_board(truth, board_pose(rng, board, 0.75, 0.32), board);
    if (!corners.empty()) views.push_back({"view", corners});
  }
  const IntrinsicsResult square = calibrate_intrinsics(views, board, cv::Size(1280, 720), {true, true});
  CHECK(square.intrinsics.fx == square.intrinsics.fy);
  CHECK(square.intrinsics.fx == Approx(truth.fx).margin(kFocalTolerancePx));
  CHECK(distortion_mismatch_px(square.intrinsics, truth, kCoveredFraction) < kDistortionTolerancePx);
}

TEST_CASE("Rendered chessboard photographs: corners found and the camera given back", "[calibration][intrinsics]") {
  CameraIntrinsics truth;
  truth.width = 640;
  truth.height = 480;
  truth.fx = 540.0;
  truth.fy = 538.0;
  truth.cx = 322.0;
  truth.cy = 244.0;
  truth.distortion.k1 = -0.25;
  truth.distortion.k2 = 0.08;
  truth.distortion.p1 = 0.001;
  truth.distortion.p2 = -0.0005;
  const Chessboard board = parse_chessboard("9x6", 0.025);
  const auto folder = scratch_folder_calibration_intrinsics("rendered");
  std::mt19937 rng(3);
  std::vector<std::filesystem::path> images;
  std::vector<std::vector<cv::Point2f>> true_corners;
  while (images.size() < 10) {
    const Eigen::Isometry3d pose = board_pose(rng, board, 0.42, 0.1);
    auto corners = project_board(truth, pose, board);
    if (corners.empty()) continue;
    const auto path = folder / ("board" + std::to_string(images.size()) + ".png");
    REQUIRE(cv::imwrite(path.string(), render_chessboard(truth, pose, board)));
    images.push_back(path);
    true_corners.push_back(corners);
  }
  // A picture without a board is named, not fatal.
  const auto empty_path = folder / "no_board.png";
  REQUIRE(cv::imwrite(empty_path.string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(128))));
  images.push_back(empty_path);

  for (size_t i = 0; i < true_corners.size(); ++i) {
    const auto found = find_chessboard(read_gray_image(images[i]), board);
    REQUIRE(found);
    double worst = 0;
    for (size_t c = 0; c < found->size(); ++c) worst = std::max(worst, double(cv::norm((*found)[c] - true_corners[i][c])));
    CHECK(worst < kRenderedCornerTolerancePx);
  }

  const ImageSetCalibration calibration = calibrate_intrinsics_from_images(images, board);
  REQUIRE(calibration.board_not_found == std::vector<std::filesystem::path>{empty_path});
  CHECK(calibration.used_images.size() == true_corners.size());
  const CameraIntrinsics& found = calibration.result.intrinsics;
  CHECK(found.fx == Approx(truth.fx).epsilon(kRenderedFocalToleranceRelative));
  CHECK(found.fy == Approx(truth.fy).epsilon(kRenderedFocalToleranceRelative));
  CHECK(found.cx == Approx(truth.cx).margin(kRenderedPrincipalPointTolerancePx));
  CHECK(found.cy == Approx(truth.cy).margin(kRenderedPrincipalPointTolerancePx));
  CHECK(calibration.result.rms_error_px < kRenderedCornerTolerancePx);
}

TEST_CASE("The opencv-doc photographs give OpenCV's reference camera", "[calibration][intrinsics][photographs]") {
  INFO("needs Debian's opencv-doc in " << kOpenCvDataCalibrationIntrinsics);
  REQUIRE(std::filesystem::exists(kOpenCvDataCalibrationIntrinsics / "left01.jpg"));
  const CameraIntrinsics reference = reference_left_intrinsics();
  const Chessboard board = parse_chessboard("9x6", 0.025);
  const auto images = expand_image_patterns({(kOpenCvDataCalibrationIntrinsics / "left*.jpg").string()});
  REQUIRE(images.size() == 14);  // left01..left14 without left10, and left.jpg, a scene without the board

  const ImageSetCalibration calibration = calibrate_intrinsics_from_images(images, board);
  CHECK(calibration.board_not_found == std::vector<std::filesystem::path>{kOpenCvDataCalibrationIntrinsics / "left.jpg"});
  CHECK(calibration.used_images.size() == 13);
  const IntrinsicsResult& result = calibration.result;
  const CameraIntrinsics& found = result.intrinsics;
  CHECK(found.width == reference.width);
  CHECK(found.height == reference.height);
  CHECK(result.rms_error_px < kPhotoMaxRmsPx);
  for (double e : result.view_rms_error_px) CHECK(e < 2 * kPhotoMaxRmsPx);
  CHECK(found.fx == Approx(reference.fx).epsilon(kPhotoFocalToleranceRelative));
  CHECK(found.fy == Approx(reference.fy).epsilon(kPhotoFocalToleranceRelative));
  CHECK(found.cx == Approx(reference.cx).margin(kPhotoPrincipalPointTolerancePx));
  CHECK(found.cy == Approx(reference.cy).margin(kPhotoPrincipalPointTolerancePx));
  INFO("distortion mismatch " << distortion_mismatch_px(found, reference, kCoveredFraction) << " px");
  CHECK(distortion_mismatch_px(found, reference, kCoveredFraction) < kPhotoDistortionTolerancePx);
  // The reference is barrel-distorted (k1 < 0); so must the estimate be.
  CHECK(found.distortion.k1 < -0.2);

  const nlohmann::json report = intrinsics_report_json(calibration, board, {});
  for (const char* field : {"fx", "fy", "cx", "cy", "width", "height", "rms_error_px"}) CHECK(report[field].is_number());
  CHECK(report["std_dev_px"]["fx"].get<double>() == result.std_dev_px.fx);
  CHECK(report["distortion"]["k1"].get<double>() == found.distortion.k1);
  REQUIRE(report["per_image"].size() == 13);
  CHECK(report["per_image"][0]["image"] == (kOpenCvDataCalibrationIntrinsics / "left01.jpg").string());
  CHECK(report["per_image"][0]["rms_error_px"].get<double>() == result.view_rms_error_px[0]);
  CHECK(report["board_not_found"] == nlohmann::json::array({(kOpenCvDataCalibrationIntrinsics / "left.jpg").string()}));
  const CameraIntrinsics read_back = intrinsics_from_json(report, "report");
  CHECK(read_back.fx == found.fx);
  CHECK(read_back.distortion.k3 == found.distortion.k3);
}

TEST_CASE("Intrinsics input errors say what is wrong", "[calibration][intrinsics]") {
  const Chessboard board = parse_chessboard("9x6", 0.025);
  const auto folder = scratch_folder_calibration_intrinsics("errors");

  SECTION("patterns that match nothing, paths that do not exist") {
    CHECK_THROWS_WITH(expand_image_patterns({(folder / "*.jpg").string()}), Contains("matches no file"));
    CHECK_THROWS_WITH(expand_image_patterns({(folder / "missing.jpg").string()}), Contains("does not exist"));
    CHECK_THROWS_WITH(expand_image_patterns({"/no/such/folder/*.png"}), Contains("/no/such/folder/*.png"));
    CHECK_THROWS_WITH(expand_image_patterns({}), Contains("no images"));
  }
  SECTION("files that are not images, or gzip-compressed") {
    std::ofstream(folder / "text.jpg") << "not a picture";
    CHECK_THROWS_WITH(read_gray_image(folder / "text.jpg"), Contains("cannot be read as an image"));
    const unsigned char gzip_header[] = {0x1f, 0x8b, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00};
    std::ofstream(folder / "left01.jpg.gz", std::ios::binary).write(reinterpret_cast<const char*>(gzip_header), 8);
    CHECK_THROWS_WITH(read_gray_image(folder / "left01.jpg.gz"), Contains("gzip-compressed"));
  }
  SECTION("too few views name the images without a board") {
    cv::imwrite((folder / "grey.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(100)));
    const std::vector<std::filesystem::path> images{kOpenCvDataCalibrationIntrinsics / "left01.jpg", kOpenCvDataCalibrationIntrinsics / "left02.jpg",
                                                    folder / "grey.png"};
    CHECK_THROWS_WITH(calibrate_intrinsics_from_images(images, board),
                      Contains("found in 2 of 3 images, at least 3") && Contains("grey.png"));
  }
  SECTION("images of different sizes") {
    cv::Mat larger;
    cv::resize(cv::imread((kOpenCvDataCalibrationIntrinsics / "left04.jpg").string()), larger, cv::Size(800, 600), 0, 0, cv::INTER_LINEAR);
    cv::imwrite((folder / "left04_larger.png").string(), larger);
    const std::vector<std::filesystem::path> images{kOpenCvDataCalibrationIntrinsics / "left01.jpg", kOpenCvDataCalibrationIntrinsics / "left02.jpg",
                                                    kOpenCvDataCalibrationIntrinsics / "left03.jpg", folder / "left04_larger.png"};
    CHECK_THROWS_WITH(calibrate_intrinsics_from_images(images, board),
                      Contains("different sizes") && Contains("640x480") && Contains("800x600"));
  }
  SECTION("views that do not match the board") {
    std::vector<BoardView> views(3, BoardView{"short", std::vector<cv::Point2f>(53, {1, 1})});
    CHECK_THROWS_WITH(calibrate_intrinsics(views, board, cv::Size(640, 480)), Contains("53 corners"));
    views.resize(2);
    CHECK_THROWS_WITH(calibrate_intrinsics(views, board, cv::Size(640, 480)), Contains("at least 3 views"));
  }
}
