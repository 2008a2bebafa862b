#include "calibration/synthetic_board_image.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "calibration/calibration_error.h"

namespace rt::calibration {
namespace {

constexpr int kTexelsPerSquare = 64;
// The undistorted image is drawn this many times finer, then averaged down: the edges get the
// partial coverage a real sensor integrates, which the sub-pixel refinement relies on.
constexpr int kSupersampling = 4;
constexpr uchar kBackground = 128;
// Undistorted coordinates further out than this many image sizes come from the far tails of
// the distortion polynomial, where it folds back; they are left as background.
constexpr double kMaxIdealExtent = 1.0;

cv::Mat board_texture(const Chessboard& board) {
  // One white square of margin on each side of the (cols + 1) x (rows + 1) squares.
  const int squares_x = board.cols + 3, squares_y = board.rows + 3;
  cv::Mat texture(squares_y * kTexelsPerSquare, squares_x * kTexelsPerSquare, CV_8UC1, cv::Scalar(255));
  for (int j = 0; j <= board.rows; ++j)
    for (int i = 0; i <= board.cols; ++i)
      if ((i + j) % 2 == 0)
        texture(cv::Rect((i + 1) * kTexelsPerSquare, (j + 1) * kTexelsPerSquare, kTexelsPerSquare, kTexelsPerSquare))
            .setTo(0);
  return texture;
}

// Board plane (X, Y, 1) from a texel centre (u, v, 1); inner corner (0, 0) lies two squares in.
Eigen::Matrix3d board_from_texel(const Chessboard& board) {
  const double metres_per_texel = board.square_m / kTexelsPerSquare;
  Eigen::Matrix3d m;
  m << metres_per_texel, 0, (0.5 - 2.0 * kTexelsPerSquare) * metres_per_texel,  //
      0, metres_per_texel, (0.5 - 2.0 * kTexelsPerSquare) * metres_per_texel,    //
      0, 0, 1;
  return m;
}

// Where each output pixel's ray meets the undistorted image plane, in pixels, row by row.
// Undistorting is iterative and slow, and the map is smooth: it is computed on a grid every
// kMapStep pixels and interpolated bilinearly (well under 0.01 px off for lens distortion).
std::vector<cv::Point2f> undistorted_pixel_positions(const CameraIntrinsics& k) {
  constexpr int kMapStep = 4;
  const int width = int(k.width), height = int(k.height);
  const int grid_width = (width - 1) / kMapStep + 2, grid_height = (height - 1) / kMapStep + 2;
  std::vector<cv::Point2f> grid;
  for (int j = 0; j < grid_height; ++j)
    for (int i = 0; i < grid_width; ++i) grid.emplace_back(float(i * kMapStep), float(j * kMapStep));
  const cv::Matx33d camera_matrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const auto coefficients = k.distortion.as_opencv();
  std::vector<cv::Point2f> grid_ideal;
  cv::undistortPoints(grid, grid_ideal, camera_matrix, cv::Mat(1, 8, CV_64F, const_cast<double*>(coefficients.data())),
                      cv::noArray(), camera_matrix);
  std::vector<cv::Point2f> ideal;
  ideal.reserve(size_t(width) * size_t(height));
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const int i = u / kMapStep, j = v / kMapStep;
      const float fu = float(u % kMapStep) / kMapStep, fv = float(v % kMapStep) / kMapStep;
      auto at = [&](int di, int dj) { return grid_ideal[size_t((j + dj) * grid_width + i + di)]; };
      ideal.push_back((at(0, 0) * (1 - fu) + at(1, 0) * fu) * (1 - fv) + (at(0, 1) * (1 - fu) + at(1, 1) * fu) * fv);
    }
  return ideal;
}

}  // namespace

cv::Mat render_chessboard(const CameraIntrinsics& k, const Eigen::Isometry3d& camera_from_board,
                          const Chessboard& board) {
  const cv::Size size(int(k.width), int(k.height));
  if (size.area() <= 0) throw CalibrationError("render_chessboard: the intrinsics have no image size");

  std::vector<cv::Point2f> ideal = undistorted_pixel_positions(k);
  const float low_x = float(-kMaxIdealExtent * size.width), high_x = float((1 + kMaxIdealExtent) * size.width);
  const float low_y = float(-kMaxIdealExtent * size.height), high_y = float((1 + kMaxIdealExtent) * size.height);
  float min_x = high_x, min_y = high_y, max_x = low_x, max_y = low_y;
  for (cv::Point2f& p : ideal) {
    if (!(p.x > low_x && p.x < high_x && p.y > low_y && p.y < high_y)) {
      p = {-1e6f, -1e6f};  // remap gives such pixels the background
      continue;
    }
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  if (!(min_x <= max_x && min_y <= max_y))
    throw CalibrationError("render_chessboard: the distortion maps no pixel into the image plane");
  const cv::Point origin(int(std::floor(min_x)) - 2, int(std::floor(min_y)) - 2);
  const cv::Size canvas(int(std::ceil(max_x)) + 3 - origin.x, int(std::ceil(max_y)) + 3 - origin.y);

  // The undistorted view of the board, drawn finely through the plane's homography, only
  // over the board's bounding box (the rest is background).
  Eigen::Matrix3d plane;
  plane.col(0) = camera_from_board.linear().col(0);
  plane.col(1) = camera_from_board.linear().col(1);
  plane.col(2) = camera_from_board.translation();
  const cv::Mat texture = board_texture(board);
  const Eigen::Matrix3d camera_from_texel = plane * board_from_texel(board);
  double min_u = 1e300, min_v = 1e300, max_u = -1e300, max_v = -1e300;
  for (const Eigen::Vector3d& texel : {Eigen::Vector3d(-0.5, -0.5, 1), Eigen::Vector3d(texture.cols - 0.5, -0.5, 1),
                                      Eigen::Vector3d(-0.5, texture.rows - 0.5, 1),
                                      Eigen::Vector3d(texture.cols - 0.5, texture.rows - 0.5, 1)}) {
    const Eigen::Vector3d ray = camera_from_texel * texel;
    if (!(ray.z() > 1e-6)) throw CalibrationError("render_chessboard: the board reaches behind the camera");
    const double u = k.fx * ray.x() / ray.z() + k.cx - origin.x, v = k.fy * ray.y() / ray.z() + k.cy - origin.y;
    min_u = std::min(min_u, u), max_u = std::max(max_u, u), min_v = std::min(min_v, v), max_v = std::max(max_v, v);
  }
  const cv::Rect board_box = cv::Rect(cv::Point(int(std::floor(std::max(min_u, -1.0))), int(std::floor(std::max(min_v, -1.0)))),
                                      cv::Point(int(std::ceil(std::min(max_u, canvas.width + 1.0))) + 1,
                                                int(std::ceil(std::min(max_v, canvas.height + 1.0))) + 1)) &
                             cv::Rect(cv::Point(0, 0), canvas);
  cv::Mat undistorted(canvas, CV_8UC1, cv::Scalar(kBackground));
  if (board_box.area() > 0) {
    const double s = kSupersampling;
    Eigen::Matrix3d fine_from_camera;  // fine pixel centres of the box from camera coordinates
    fine_from_camera << s * k.fx, 0, s * (k.cx - origin.x - board_box.x + 0.5) - 0.5,  //
        0, s * k.fy, s * (k.cy - origin.y - board_box.y + 0.5) - 0.5,                   //
        0, 0, 1;
    const Eigen::Matrix3d homography = fine_from_camera * camera_from_texel;
    cv::Matx33d cv_homography;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) cv_homography(r, c) = homography(r, c);
    cv::Mat fine;
    cv::warpPerspective(texture, fine, cv_homography, board_box.size() * kSupersampling, cv::INTER_LINEAR,
                        cv::BORDER_CONSTANT, cv::Scalar(kBackground));
    cv::resize(fine, undistorted(board_box), board_box.size(), 0, 0, cv::INTER_AREA);
  }

  cv::Mat map(size, CV_32FC2);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const cv::Point2f p = ideal[size_t(v * size.width + u)];
      map.at<cv::Vec2f>(v, u) = {p.x - float(origin.x), p.y - float(origin.y)};
    }
  cv::Mat image;
  cv::remap(undistorted, image, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(kBackground));
  return image;
}

}  // namespace rt::calibration
