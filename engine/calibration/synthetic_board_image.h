#pragma once
// A photograph of a chessboard as a camera with known intrinsics (distortion included) would
// take it from a known pose: ground truth for testing the corner finder and the calibration.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "calibration/chessboard.h"
#include "geometry/camera.h"

namespace rt::calibration {

// 8-bit grey, intrinsics.width x intrinsics.height: black and white squares (the outer
// top-left one black) on a white margin one square wide, on a mid-grey background,
// anti-aliased. `camera_from_board` maps the board frame of Chessboard::object_points.
cv::Mat render_chessboard(const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& camera_from_board,
                          const Chessboard& board);

}  // namespace rt::calibration
