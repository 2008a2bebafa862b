// The eye detector's set-up, its answers to images that hold no face or are not images it can
// use, and the iris refinement on a drawn eye. Detection on a real face is tested on the
// synthetic renders (test_viewer_renders).
#include <catch2/catch.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <fstream>

#include "viewer/eye_detector.h"
#include "viewer/iris_centre.h"

TEST_CASE("the cascades' folder defaults to Debian's and a missing file names itself and the package", "[viewer][detector]") {
  CHECK(rt::EyeDetectorOptions{}.cascade_directory == std::filesystem::path("/usr/share/opencv4/haarcascades"));

  rt::EyeDetectorOptions options;
  options.cascade_directory = "/nonexistent/haarcascades";
  CHECK_THROWS_AS(rt::EyeDetector(options), rt::EyeDetectorSetupError);
  CHECK_THROWS_WITH(rt::EyeDetector(options), Catch::Contains("/nonexistent/haarcascades/haarcascade_frontalface_alt2.xml") &&
                                                  Catch::Contains("opencv-data") && Catch::Contains("cascade_directory"));

  options = {};
  options.eye_cascades.push_back("haarcascade_no_such_eye.xml");
  CHECK_THROWS_WITH(rt::EyeDetector(options), Catch::Contains("haarcascade_no_such_eye.xml") && Catch::Contains("not found"));
  options.eye_cascades.clear();
  CHECK_THROWS_WITH(rt::EyeDetector(options), Catch::Contains("at least one"));
}

TEST_CASE("a cascade file that is not a cascade is refused at set-up", "[viewer][detector]") {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "remotetouch-test-eye-detector";
  std::filesystem::create_directories(folder);
  for (const char* name : {"haarcascade_frontalface_alt2.xml", "haarcascade_eye.xml", "haarcascade_eye_tree_eyeglasses.xml",
                           "haarcascade_lefteye_2splits.xml", "haarcascade_righteye_2splits.xml"})
    std::ofstream(folder / name) << "this is not a cascade\n";
  rt::EyeDetectorOptions options;
  options.cascade_directory = folder;
  CHECK_THROWS_WITH(rt::EyeDetector(options), Catch::Contains("could not be read") && Catch::Contains("opencv-data"));
  std::filesystem::remove_all(folder);
}

TEST_CASE("options that cannot work are refused at set-up", "[viewer][detector]") {
  rt::EyeDetectorOptions options;
  options.eye_scale_step = 1.0;
  CHECK_THROWS_WITH(rt::EyeDetector(options), Catch::Contains("must be > 1"));
  options = {};
  options.min_face_px = 10;
  CHECK_THROWS_WITH(rt::EyeDetector(options), Catch::Contains("min_face_px"));
}

TEST_CASE("images it cannot use are invalid input; images without a face find nothing", "[viewer][detector]") {
  rt::EyeDetector detector;
  const rt::EyeDetection empty = detector.detect(cv::Mat());
  CHECK(empty.failure == rt::ViewerFailure::InvalidInput);
  CHECK_THAT(empty.message, Catch::Contains("empty"));

  const rt::EyeDetection floating = detector.detect(cv::Mat(360, 640, CV_32FC3, cv::Scalar::all(0.5)));
  CHECK(floating.failure == rt::ViewerFailure::InvalidInput);
  CHECK_THAT(floating.message, Catch::Contains("8-bit"));
  CHECK(detector.detect(cv::Mat(360, 640, CV_16UC1, cv::Scalar(1000))).failure == rt::ViewerFailure::InvalidInput);
  CHECK(detector.detect(cv::Mat(360, 640, CV_8UC2, cv::Scalar(1, 2))).failure == rt::ViewerFailure::InvalidInput);

  // A plain wall and a smooth gradient: no face, for grey, BGR and BGRA input alike.
  cv::Mat gradient(360, 640, CV_8UC1);
  for (int y = 0; y < gradient.rows; ++y)
    for (int x = 0; x < gradient.cols; ++x) gradient.at<uint8_t>(y, x) = uint8_t((x + y) * 255 / (640 + 360));
  for (const cv::Mat& image : {cv::Mat(360, 640, CV_8UC1, cv::Scalar(128)), cv::Mat(360, 640, CV_8UC3, cv::Scalar(90, 120, 160)),
                               cv::Mat(360, 640, CV_8UC4, cv::Scalar(90, 120, 160, 255)), gradient}) {
    const rt::EyeDetection detection = detector.detect(image);
    CHECK(detection.failure == rt::ViewerFailure::EyesNotFound);
    CHECK_THAT(detection.message, Catch::Contains("no frontal face"));
  }
}

namespace {

// A synthetic eye in a 60x60 eye box: skin, an almond of sclera, an iris with a pupil, centred
// off the box's centre. Drawn 8x larger and shrunk, so its edges are anti-aliased and the iris
// centre can sit between pixels.
cv::Mat synthetic_eye(const Eigen::Vector2d& iris_centre_px) {
  constexpr int kScale = 8;
  cv::Mat large(60 * kScale, 60 * kScale, CV_8UC1, cv::Scalar(170));
  auto at = [&](const Eigen::Vector2d& p) { return cv::Point(int((p.x() + 0.5) * kScale), int((p.y() + 0.5) * kScale)); };
  cv::ellipse(large, at({30, 32}), cv::Size(22 * kScale, 10 * kScale), 0, 0, 360, cv::Scalar(225), cv::FILLED);
  cv::circle(large, at(iris_centre_px), 7 * kScale, cv::Scalar(95), cv::FILLED);
  cv::circle(large, at(iris_centre_px), 3 * kScale, cv::Scalar(30), cv::FILLED);
  cv::Mat eye;
  cv::resize(large, eye, cv::Size(60, 60), 0, 0, cv::INTER_AREA);
  return eye;
}

}  // namespace

TEST_CASE("the iris centre is found from its edge, off the eye box's centre", "[viewer][detector]") {
  for (const Eigen::Vector2d& truth : {Eigen::Vector2d(34.4, 30.6), Eigen::Vector2d(25.0, 33.5), Eigen::Vector2d(29.5, 29.5)}) {
    const cv::Mat eye = synthetic_eye(truth);
    const Eigen::Vector2d found = rt::iris_centre(eye, cv::Rect(0, 0, 60, 60));
    INFO("iris at " << truth.transpose() << ", found " << found.transpose());
    // The box centre is (29.5, 29.5): the refinement must do better than it by a clear margin.
    CHECK((found - truth).norm() < 0.3);  // measured: 0.05-0.1 px
  }
  // Where nothing can be found, the box centre comes back, never a NaN.
  const cv::Mat flat(60, 60, CV_8UC1, cv::Scalar(128));
  CHECK((rt::iris_centre(flat, cv::Rect(10, 10, 30, 30)) - Eigen::Vector2d(24.5, 24.5)).norm() < 1e-12);
  CHECK((rt::iris_centre(flat, cv::Rect(10, 10, 5, 5)) - Eigen::Vector2d(12, 12)).norm() < 1e-12);
  CHECK((rt::iris_centre(flat, cv::Rect(50, 50, 30, 30)) - Eigen::Vector2d(64.5, 64.5)).norm() < 1e-12);
  CHECK(rt::iris_centre(cv::Mat(), cv::Rect(0, 0, 30, 30)).allFinite());
}
