// The viewer's eye end to end on synthetic renders: a real face photograph (Debian's opencv-doc)
// stands as a flat print at a known pose in front of the screen, the site's simulated cameras
// render it, the cascades find the eyes, and the triangulated midpoint is compared with the
// print's hand-marked pupils mapped into the site. Prints the error per camera configuration:
//   build-viewer/tests/remotetouch_cpu_tests "[renders]"
#include <catch2/catch.hpp>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <numbers>
#include <sstream>

#include "viewer/eye_locator.h"
#include "viewer/initial_viewpoint.h"
#include "viewer/simulated_views.h"

namespace {

// A frontal portrait from OpenCV's face-landmark tutorial, shipped by Debian's opencv-doc.
constexpr const char* kDefaultFacePhoto = "/usr/share/doc/opencv-doc/opencv4/html/230501201_1.jpg";
// Pupil centres, fixed by hand on 12x enlargements of that photo (pixel-centre coordinates,
// about +-1 px, i.e. +-0.5 mm on the print). The person's right eye is on the image's left.
const Eigen::Vector2d kPhotoRightPupil(244.0, 363.5);
const Eigen::Vector2d kPhotoLeftPupil(365.0, 356.0);
// The print is scaled so its pupils are the adult mean distance apart.
constexpr double kInterpupillaryM = 0.063;

// Half the Azure Kinect's 2560x1440 color mode, same 90 x 59 degree field: at 0.7 m a face
// spans ~150 px and an eye ~25 px. At 640x360 an eye is ~12 px, below what the Haar eye cascade
// (20 px window) resolves reliably; the paper works at 2560x1440.
const rt::CameraIntrinsics kRenderIntrinsics{1280, 720, 640.0, 640.0, 639.5, 359.5, {}};

// Midpoint error allowed on a render. One pixel at 0.7 m is 1.1 mm here; the detector's eye
// centre (cascade box, then iris refinement) is off by 2-4 px per view, so 2-4.5 mm per eye,
// and two to six views average that but do not remove the part every view shares (the eyes
// are found ~2 px high in all of them). 8 mm is twice the worst per-view error: a wrong eye
// pick (>= 15 px, 17 mm) or a convention slip fails it. For the renderer it is ample: a 1 cm
// eye error moves the image of the remote user (0.7 m behind the glass) by 5 mm on the screen.
constexpr double kMidpointToleranceMm = 8.0;

cv::Mat load_face_photo() {
  const char* override_path = std::getenv("REMOTETOUCH_FACE_PHOTO");
  const std::filesystem::path path = override_path ? override_path : kDefaultFacePhoto;
  cv::Mat photo = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (photo.empty())
    FAIL("face photograph '" << path.string()
                             << "' is missing or unreadable: install the Debian package opencv-doc, or set "
                                "REMOTETOUCH_FACE_PHOTO to that photo (the pupils are marked for it)");
  REQUIRE(photo.size() == cv::Size(584, 824));  // the pupils above are marked on this exact file
  return photo;
}

struct HeadPose {
  const char* name;
  Eigen::Vector3d eye_midpoint;  // site frame, metres
  double yaw_deg;                // turn about the vertical axis
};

const HeadPose kHeads[] = {
    {"centre 0.70 m", {0.00, 0.00, 0.70}, 0.0},
    {"left, near 0.62 m", {-0.15, 0.05, 0.62}, 0.0},
    {"right, far 0.80 m, turned 15 deg", {0.12, -0.05, 0.80}, 15.0},
    {"high, far 0.90 m, turned -10 deg", {0.00, 0.10, 0.90}, -10.0},
    {"low, near 0.55 m", {0.05, -0.06, 0.55}, 0.0},
};

// The print facing the screen (its image right towards site -x, its image down towards site
// -y, as a person facing the screen appears to the cameras), turned by `yaw_deg`, its pupils'
// midpoint at the head's eye midpoint.
rt::PlanarPhoto place_print(const cv::Mat& photo, const HeadPose& head) {
  rt::PlanarPhoto print;
  print.image = photo;
  print.metres_per_pixel = kInterpupillaryM / (kPhotoRightPupil - kPhotoLeftPupil).norm();
  const Eigen::Matrix3d facing_screen = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(head.yaw_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() * facing_screen;
  const Eigen::Vector2d pupils_midpoint = (kPhotoRightPupil + kPhotoLeftPupil) / 2.0 * print.metres_per_pixel;
  print.site_from_photo.linear() = rotation;
  print.site_from_photo.translation() = head.eye_midpoint - rotation * Eigen::Vector3d(pupils_midpoint.x(), pupils_midpoint.y(), 0);
  return print;
}

std::vector<rt::Camera> render_stand() {
  rt::CameraStandOptions options;
  options.intrinsics = kRenderIntrinsics;
  // Half the cameras get a real lens, so undistortion is on the path being measured.
  std::vector<rt::Camera> cameras = rt::simulated_camera_stand(options);
  for (size_t i = 0; i < cameras.size(); i += 2) {
    cameras[i].intrinsics.distortion.k1 = -0.06;
    cameras[i].intrinsics.distortion.k2 = 0.02;
  }
  return cameras;
}

struct Configuration {
  const char* name;
  std::vector<size_t> cameras;  // indices into the stand: 0 top-left .. 5 bottom-right
  bool must_succeed_everywhere;  // every head pose must give a viewpoint
};

const Configuration kConfigurations[] = {
    {"2 views: top-centre + bottom-centre", {1, 4}, false},
    {"2 views: top-left + top-right", {0, 2}, false},
    {"3 views: top-centre + bottom-centre + top-right", {1, 4, 2}, false},
    {"4 views (paper, left-hand touch): centres + right side", {1, 4, 2, 5}, true},
    {"6 views: all", {0, 1, 2, 3, 4, 5}, true},
};

std::string millimetres(double metres) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << metres * 1000.0;
  return out.str();
}

}  // namespace

TEST_CASE("the detector finds both pupils in the frontal photograph, in grey, BGR and BGRA", "[viewer][renders]") {
  const cv::Mat photo = load_face_photo();
  rt::EyeDetector detector;
  cv::Mat grey, bgra;
  cv::cvtColor(photo, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(photo, bgra, cv::COLOR_BGR2BGRA);
  for (const cv::Mat& image : {photo, grey, bgra}) {
    const rt::EyeDetection detection = detector.detect(image);
    INFO(image.channels() << " channel(s): " << detection.message);
    REQUIRE(detection.found());
    // This checks that each eye is found, not how precisely (that is measured in 3D below): the
    // eyes are ~60 px wide in this photo, the eyebrows ~40 px above the pupils, the nose bridge
    // ~60 px aside, so within 15 px is the eye. Measured: 9.4 px and 0.9 px.
    INFO("image-left eye off by " << (detection.image_left_eye - kPhotoRightPupil).norm() << " px, image-right eye by "
                                  << (detection.image_right_eye - kPhotoLeftPupil).norm() << " px");
    CHECK((detection.image_left_eye - kPhotoRightPupil).norm() < 15.0);
    CHECK((detection.image_right_eye - kPhotoLeftPupil).norm() < 15.0);
  }
}

TEST_CASE("the eye midpoint triangulated from synthetic renders, per camera configuration", "[viewer][renders]") {
  const cv::Mat photo = load_face_photo();
  const std::vector<rt::Camera> cameras = render_stand();
  rt::EyeDetector detector;

  // One render and one detection per camera and head; configurations share them.
  std::map<std::pair<size_t, size_t>, rt::ViewEyes> seen;  // (head, camera) -> labelled eyes
  std::vector<Eigen::Vector3d> truths;
  std::vector<std::vector<cv::Mat>> renders;
  for (size_t h = 0; h < std::size(kHeads); ++h) {
    const rt::PlanarPhoto print = place_print(photo, kHeads[h]);
    truths.push_back((print.pixel_in_site(kPhotoRightPupil) + print.pixel_in_site(kPhotoLeftPupil)) / 2.0);
    REQUIRE((truths.back() - kHeads[h].eye_midpoint).norm() < 1e-9);
    renders.emplace_back();
    for (size_t c = 0; c < cameras.size(); ++c) {
      renders.back().push_back(rt::render_planar_photo(print, cameras[c]));
      const rt::EyeDetection detection = detector.detect(renders.back().back());
      if (!detection.found()) continue;
      const auto labelled = rt::assign_viewer_sides(cameras[c], detection.image_left_eye, detection.image_right_eye);
      REQUIRE(labelled);
      seen[{h, c}] = {c, *labelled};
    }
  }

  std::cout << "\nEye midpoint error on synthetic renders (" << kRenderIntrinsics.width << "x" << kRenderIntrinsics.height
            << ", tolerance " << kMidpointToleranceMm << " mm):\n";
  double worst_mm = 0;
  for (const Configuration& configuration : kConfigurations) {
    std::cout << "  " << configuration.name << "\n";
    double sum_mm = 0;
    int successes = 0;
    for (size_t h = 0; h < std::size(kHeads); ++h) {
      std::vector<rt::ViewEyes> views;
      for (size_t c : configuration.cameras)
        if (auto found = seen.find({h, c}); found != seen.end()) views.push_back(found->second);
      std::cout << "    " << std::left << std::setw(34) << kHeads[h].name << std::right;
      if (views.size() < 2) {
        std::cout << "not found: eyes detected in " << views.size() << " of " << configuration.cameras.size() << " views\n";
        CHECK_FALSE(configuration.must_succeed_everywhere);
        continue;
      }
      const rt::EyePair pair = rt::triangulate_eye_pair(cameras, views);
      if (!pair.ok()) {
        std::cout << "refused (" << rt::failure_name(pair.failure) << "): " << pair.message << "\n";
        CHECK_FALSE(configuration.must_succeed_everywhere);
        continue;
      }
      const Eigen::Vector3d error = pair.midpoint - truths[h];
      const double error_mm = error.norm() * 1000;
      std::cout << "error " << std::fixed << std::setprecision(1) << std::setw(5) << error_mm << " mm  (x " << millimetres(error.x())
                << ", y " << millimetres(error.y()) << ", z " << millimetres(error.z()) << ")  views " << views.size() << "/"
                << configuration.cameras.size() << ", dropped " << pair.cameras_rejected.size() << ", eyes "
                << millimetres((pair.viewer_right - pair.viewer_left).norm()) << " mm apart\n"
                << std::defaultfloat;
      INFO(configuration.name << ", head " << kHeads[h].name);
      CHECK(pair.midpoint.allFinite());
      CHECK(error_mm < kMidpointToleranceMm);
      worst_mm = std::max(worst_mm, error_mm);
      sum_mm += error_mm;
      ++successes;
    }
    if (successes > 0)
      std::cout << "    mean " << std::fixed << std::setprecision(1) << sum_mm / successes << " mm over " << successes << " of "
                << std::size(kHeads) << " head poses\n"
                << std::defaultfloat;
  }
  std::cout << "  worst " << std::fixed << std::setprecision(1) << worst_mm << " mm\n" << std::defaultfloat;

  // The one-call path (detect, label, triangulate) on all six images of the first head.
  const rt::EyePair pair = rt::locate_viewer_eyes(detector, cameras, renders[0]);
  INFO(pair.message);
  REQUIRE(pair.ok());
  CHECK((pair.midpoint - truths[0]).norm() * 1000 < kMidpointToleranceMm);
}

TEST_CASE("fewer than two views with eyes is a clear result, not a guess", "[viewer][renders]") {
  const cv::Mat photo = load_face_photo();
  const std::vector<rt::Camera> cameras = render_stand();
  rt::EyeDetector detector;
  const rt::PlanarPhoto print = place_print(photo, kHeads[0]);

  std::vector<cv::Mat> images(cameras.size());
  const rt::EyePair none = rt::locate_viewer_eyes(detector, cameras, images);
  CHECK(none.failure == rt::ViewerFailure::EyesNotFound);
  CHECK_THAT(none.message, Catch::Contains("found in 0 view(s)"));

  images[1] = rt::render_planar_photo(print, cameras[1]);
  images[4] = cv::Mat(720, 1280, CV_8UC3, cv::Scalar::all(96));  // the viewer left this camera's view
  const rt::EyePair one = rt::locate_viewer_eyes(detector, cameras, images);
  CHECK(one.failure == rt::ViewerFailure::TooFewViews);
  CHECK_THAT(one.message, Catch::Contains("found in 1 view(s)") && Catch::Contains("camera 'bottom-centre': no frontal face"));
  CHECK(one.midpoint.allFinite());
  CHECK(one.cameras_seeing_eyes == std::vector<size_t>{1});

  images.pop_back();
  CHECK_THROWS_WITH(rt::locate_viewer_eyes(detector, cameras, images), Catch::Contains("5 images for 6 cameras"));
}

TEST_CASE("once at start on noisy renders: robust over several frames", "[viewer][renders]") {
  const cv::Mat photo = load_face_photo();
  const std::vector<rt::Camera> cameras = render_stand();
  rt::EyeDetector detector;
  const HeadPose head = kHeads[1];
  const rt::PlanarPhoto print = place_print(photo, head);
  // Three of the paper's cameras; sensor noise changes every frame.
  const std::vector<size_t> used = {1, 4, 2};
  std::vector<cv::Mat> clean(cameras.size());
  for (size_t c : used) clean[c] = rt::render_planar_photo(print, cameras[c]);

  rt::InitialViewpointOptions options;
  options.frames_needed = 4;  // the default is 15; 4 keeps the test fast and still outvotes one
  rt::InitialViewpointEstimator estimator(options);
  cv::RNG noise(1234);
  double worst_frame_mm = 0;
  for (int frame = 0; frame < 5; ++frame) {
    std::vector<cv::Mat> images(cameras.size());
    for (size_t c : used) {
      cv::Mat grain(clean[c].size(), CV_16SC3);
      noise.fill(grain, cv::RNG::NORMAL, 0, 3.0);  // about a Kinect color frame's noise in 8 bits
      cv::Mat noisy;
      clean[c].convertTo(noisy, CV_16SC3);
      noisy += grain;
      noisy.convertTo(images[c], CV_8UC3);
    }
    const rt::EyePair pair = rt::locate_viewer_eyes(detector, cameras, images);
    if (pair.ok()) worst_frame_mm = std::max(worst_frame_mm, (pair.midpoint - head.eye_midpoint).norm() * 1000);
    estimator.add(uint64_t(frame) * 33'333, pair);
  }
  // A wrong frame, as a detection of a face in a poster would give: outvoted by the median.
  rt::EyePair poster;
  poster.midpoint = head.eye_midpoint + Eigen::Vector3d(0.3, 0.1, 0.4);
  estimator.add(5 * 33'333, poster);

  const rt::InitialViewpoint result = estimator.result();
  INFO(result.message);
  REQUIRE(result.ok());
  const double error_mm = (result.midpoint - head.eye_midpoint).norm() * 1000;
  std::cout << "\nOnce at start (" << head.name << ", 3 views, 5 noisy frames + 1 poster frame): error " << std::fixed
            << std::setprecision(1) << error_mm << " mm from " << result.frames_used << " frames (worst single frame "
            << worst_frame_mm << " mm), " << result.frames_outliers << " outlier(s) dropped\n"
            << std::defaultfloat;
  CHECK(result.frames_outliers >= 1);
  CHECK(error_mm < kMidpointToleranceMm);
}
