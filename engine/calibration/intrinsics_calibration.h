#pragma once
// Zhang's method: a camera's focal lengths, principal point and lens distortion from several
// views of a planar chessboard (OpenCV's calibrateCamera), with the reprojection error of
// every view so that a bad photograph can be found and left out.
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "calibration/chessboard.h"
#include "geometry/camera.h"

namespace rt::calibration {

// Fewer views leave the focal length and the principal point poorly constrained; OpenCV
// itself accepts one.
constexpr size_t kMinIntrinsicsViews = 3;

struct IntrinsicsOptions {
  bool fix_aspect_ratio = false;  // fx = fy (square pixels), as OpenCV's reference run did
  bool rational_model = false;    // also k4, k5, k6 (wide-angle lenses such as the Kinect's)
};

struct BoardView {
  std::string label;                // the image's path, or a name for synthetic views
  std::vector<cv::Point2f> corners; // in the board's corner order
};

// OpenCV's estimate of the standard deviations, from the residuals and the fit's Jacobian.
struct IntrinsicsStdDev {
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
};

struct IntrinsicsResult {
  CameraIntrinsics intrinsics;
  IntrinsicsStdDev std_dev_px;
  double rms_error_px = 0;
  std::vector<double> view_rms_error_px;  // one per view, in the views' order
};

// Throws when there are fewer than kMinIntrinsicsViews views, a view's corner count does not
// match the board, or the solver's result is not finite.
IntrinsicsResult calibrate_intrinsics(const std::vector<BoardView>& views, const Chessboard& board,
                                      cv::Size image_size, const IntrinsicsOptions& options = {});

struct ImageSetCalibration {
  IntrinsicsResult result;
  std::vector<std::filesystem::path> used_images;  // in the order of view_rms_error_px
  std::vector<std::filesystem::path> board_not_found;
};

// Finds the board in every image and calibrates from those where it was found. Images where
// it was found must all have the same size; too few detections is an error that names the
// images where the board was not found.
ImageSetCalibration calibrate_intrinsics_from_images(const std::vector<std::filesystem::path>& images,
                                                     const Chessboard& board, const IntrinsicsOptions& options = {});

// The camera JSON (rt::intrinsics_to_json) plus rms_error_px, per_image errors, the images
// where the board was not found, and the board.
nlohmann::json intrinsics_report_json(const ImageSetCalibration& calibration, const Chessboard& board,
                                      const IntrinsicsOptions& options);

}  // namespace rt::calibration
