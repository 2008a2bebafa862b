#include "calibration/intrinsics_calibration.h"

#include <opencv2/calib3d.hpp>

#include <cmath>

#include "calibration/calibration_error.h"
#include "calibration/image_files.h"

namespace rt::calibration {
namespace {

std::string size_text(cv::Size size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

void check_view(const BoardView& view, const Chessboard& board) {
  if (view.corners.size() != board.corner_count())
    throw CalibrationError("view '" + view.label + "' has " + std::to_string(view.corners.size()) +
                           " corners, the board has " + std::to_string(board.corner_count()));
  for (const cv::Point2f& corner : view.corners)
    if (!std::isfinite(corner.x) || !std::isfinite(corner.y))
      throw CalibrationError("view '" + view.label + "' has a non-finite corner");
}

CameraIntrinsics intrinsics_from_opencv(const cv::Mat& camera_matrix, const cv::Mat& distortion, cv::Size size) {
  CameraIntrinsics k;
  k.width = uint32_t(size.width);
  k.height = uint32_t(size.height);
  k.fx = camera_matrix.at<double>(0, 0);
  k.fy = camera_matrix.at<double>(1, 1);
  k.cx = camera_matrix.at<double>(0, 2);
  k.cy = camera_matrix.at<double>(1, 2);
  const cv::Mat coefficients = distortion.reshape(1, 1);
  k.distortion = Distortion::from_opencv(coefficients.ptr<double>(), coefficients.total());
  return k;
}

bool all_finite(const CameraIntrinsics& k) {
  const auto d = k.distortion.as_opencv();
  bool finite = std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) && std::isfinite(k.cy);
  for (double c : d) finite = finite && std::isfinite(c);
  return finite;
}

}  // namespace

IntrinsicsResult calibrate_intrinsics(const std::vector<BoardView>& views, const Chessboard& board,
                                      cv::Size image_size, const IntrinsicsOptions& options) {
  if (views.size() < kMinIntrinsicsViews)
    throw CalibrationError("intrinsics need at least " + std::to_string(kMinIntrinsicsViews) +
                           " views of the board, have " + std::to_string(views.size()));
  if (image_size.width <= 0 || image_size.height <= 0) throw CalibrationError("image size must be positive");
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const BoardView& view : views) {
    check_view(view, board);
    object_points.push_back(board.object_points());
    image_points.push_back(view.corners);
  }

  // With a fixed aspect ratio OpenCV takes fx/fy from the initial matrix: 1 means square pixels.
  cv::Mat camera_matrix = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat distortion;
  int flags = 0;
  if (options.fix_aspect_ratio) flags |= cv::CALIB_FIX_ASPECT_RATIO;
  if (options.rational_model) flags |= cv::CALIB_RATIONAL_MODEL;
  std::vector<cv::Mat> rotations, translations;
  cv::Mat intrinsics_deviation, extrinsics_deviation, view_errors;
  IntrinsicsResult result;
  try {
    result.rms_error_px = cv::calibrateCamera(object_points, image_points, image_size, camera_matrix, distortion,
                                              rotations, translations, intrinsics_deviation, extrinsics_deviation,
                                              view_errors, flags);
  } catch (const cv::Exception& error) {
    throw CalibrationError(std::string("OpenCV's calibrateCamera failed (are the views degenerate, e.g. all "
                                       "fronto-parallel?): ") + error.what());
  }
  result.intrinsics = intrinsics_from_opencv(camera_matrix, distortion, image_size);
  for (int i = 0; i < int(view_errors.total()); ++i) result.view_rms_error_px.push_back(view_errors.at<double>(i));
  if (intrinsics_deviation.total() >= 4) {
    const double* deviation = intrinsics_deviation.ptr<double>();
    result.std_dev_px = {deviation[0], deviation[1], deviation[2], deviation[3]};
    // With the aspect ratio fixed OpenCV estimates fy alone and reports 0 for fx = fy.
    if (options.fix_aspect_ratio) result.std_dev_px.fx = result.std_dev_px.fy;
  }
  bool finite = all_finite(result.intrinsics) && std::isfinite(result.rms_error_px) &&
                std::isfinite(result.std_dev_px.fx) && std::isfinite(result.std_dev_px.fy) &&
                std::isfinite(result.std_dev_px.cx) && std::isfinite(result.std_dev_px.cy);
  for (double e : result.view_rms_error_px) finite = finite && std::isfinite(e);
  if (!finite || !(result.intrinsics.fx > 0) || !(result.intrinsics.fy > 0))
    throw CalibrationError("the calibration did not converge to a valid camera (non-finite or non-positive focal "
                           "length); the views may be degenerate: tilt the board between views");
  return result;
}

ImageSetCalibration calibrate_intrinsics_from_images(const std::vector<std::filesystem::path>& images,
                                                     const Chessboard& board, const IntrinsicsOptions& options) {
  ImageSetCalibration calibration;
  std::vector<BoardView> views;
  cv::Size image_size;
  std::filesystem::path first_with_board;
  for (const std::filesystem::path& path : images) {
    const cv::Mat gray = read_gray_image(path);
    const auto corners = find_chessboard(gray, board);
    if (!corners) {
      calibration.board_not_found.push_back(path);
      continue;
    }
    if (views.empty()) {
      image_size = gray.size();
      first_with_board = path;
    } else if (gray.size() != image_size) {
      throw CalibrationError("images of different sizes: '" + first_with_board.string() + "' is " +
                             size_text(image_size) + ", '" + path.string() + "' is " + size_text(gray.size()) +
                             "; calibrate each camera and resolution on its own");
    }
    views.push_back({path.string(), *corners});
    calibration.used_images.push_back(path);
  }
  if (views.size() < kMinIntrinsicsViews) {
    std::string message = "the board (" + board.describe() + ") was found in " + std::to_string(views.size()) +
                          " of " + std::to_string(images.size()) + " images, at least " +
                          std::to_string(kMinIntrinsicsViews) + " are needed";
    if (calibration.board_not_found.empty()) throw CalibrationError(message + ": take more photographs");
    message += " (is the board given as its inner corners, COLSxROWS?); not found in:";
    for (const auto& path : calibration.board_not_found) message += "\n  " + path.string();
    throw CalibrationError(message);
  }
  calibration.result = calibrate_intrinsics(views, board, image_size, options);
  return calibration;
}

nlohmann::json intrinsics_report_json(const ImageSetCalibration& calibration, const Chessboard& board,
                                      const IntrinsicsOptions& options) {
  nlohmann::json json = intrinsics_to_json(calibration.result.intrinsics);
  json["rms_error_px"] = calibration.result.rms_error_px;
  const IntrinsicsStdDev& deviation = calibration.result.std_dev_px;
  json["std_dev_px"] = {{"fx", deviation.fx}, {"fy", deviation.fy}, {"cx", deviation.cx}, {"cy", deviation.cy}};
  nlohmann::json per_image = nlohmann::json::array();
  for (size_t i = 0; i < calibration.used_images.size(); ++i)
    per_image.push_back({{"image", calibration.used_images[i].string()},
                         {"rms_error_px", calibration.result.view_rms_error_px.at(i)}});
  json["per_image"] = per_image;
  nlohmann::json not_found = nlohmann::json::array();
  for (const auto& path : calibration.board_not_found) not_found.push_back(path.string());
  json["board_not_found"] = not_found;
  json["board"] = {{"cols", board.cols}, {"rows", board.rows}, {"square_m", board.square_m}};
  json["model"] = {{"fix_aspect_ratio", options.fix_aspect_ratio}, {"rational_model", options.rational_model}};
  return json;
}

}  // namespace rt::calibration
