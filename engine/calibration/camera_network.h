#pragma once
// The cameras' poses relative to one reference camera, from chessboard views that two or more
// cameras took at the same moment. Each camera is linked to the camera it shares the most
// views with (a maximum spanning tree grown from the reference); every link is one
// cv::stereoCalibrate with the intrinsics held fixed, and the links are chained.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "calibration/chessboard.h"
#include "geometry/camera.h"

namespace rt::calibration {

// Views of one link that disagree by more than this are not noise: most often one camera
// numbered the board's corners from the other end, or the views were not simultaneous.
constexpr double kMaxLinkRmsPx = 2.0;

struct CameraObservation {
  std::string camera;
  std::vector<cv::Point2f> corners;  // the whole board, in its corner order
};

// One moment: the board as every camera that saw it whole.
struct BoardSnapshot {
  std::string name;
  std::vector<CameraObservation> observations;
};

struct NamedIntrinsics {
  std::string name;
  CameraIntrinsics intrinsics;
};

struct CameraLink {
  std::string camera;
  std::string linked_to;  // the camera it was chained from; empty for the reference
  Eigen::Isometry3d camera_from_reference = Eigen::Isometry3d::Identity();
  size_t shared_views = 0;
  double rms_error_px = 0;  // of the stereo calibration of this link, both cameras
};

// One link per camera, in the order of `cameras`. Throws when the reference is unknown, a
// camera shares no view with the others, an observation names an unknown camera or has the
// wrong corner count, or a link's RMS exceeds `max_link_rms_px`.
std::vector<CameraLink> link_cameras(const std::vector<NamedIntrinsics>& cameras,
                                     const std::vector<BoardSnapshot>& snapshots, const Chessboard& board,
                                     const std::string& reference, double max_link_rms_px = kMaxLinkRmsPx);

}  // namespace rt::calibration
