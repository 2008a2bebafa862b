#include "calibration/camera_network.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include "calibration/calibration_error.h"

namespace rt::calibration {
namespace {

cv::Mat camera_matrix(const CameraIntrinsics& k) { return (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1); }

cv::Mat distortion_coefficients(const CameraIntrinsics& k) {
  const auto coefficients = k.distortion.as_opencv();
  return cv::Mat(1, int(coefficients.size()), CV_64F, const_cast<double*>(coefficients.data())).clone();
}

// corners[snapshot][camera]: the camera's view of that snapshot, if it saw the board.
using CornerTable = std::vector<std::vector<std::optional<std::vector<cv::Point2f>>>>;

CornerTable tabulate(const std::vector<NamedIntrinsics>& cameras, const std::vector<BoardSnapshot>& snapshots,
                     const Chessboard& board) {
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < cameras.size(); ++i)
    if (!index.emplace(cameras[i].name, i).second)
      throw CalibrationError("camera name '" + cameras[i].name + "' appears twice");
  CornerTable table(snapshots.size(), std::vector<std::optional<std::vector<cv::Point2f>>>(cameras.size()));
  for (size_t s = 0; s < snapshots.size(); ++s)
    for (const CameraObservation& observation : snapshots[s].observations) {
      const std::string where = "view '" + snapshots[s].name + "', camera '" + observation.camera + "'";
      const auto it = index.find(observation.camera);
      if (it == index.end()) throw CalibrationError(where + ": no such camera in the camera list");
      if (observation.corners.size() != board.corner_count())
        throw CalibrationError(where + ": " + std::to_string(observation.corners.size()) + " corners, the board has " +
                               std::to_string(board.corner_count()));
      for (const cv::Point2f& corner : observation.corners)
        if (!std::isfinite(corner.x) || !std::isfinite(corner.y)) throw CalibrationError(where + ": a corner is not finite");
      if (table[s][it->second]) throw CalibrationError(where + ": the camera appears twice in this view");
      table[s][it->second] = observation.corners;
    }
  return table;
}

size_t shared_views(const CornerTable& table, size_t a, size_t b) {
  size_t count = 0;
  for (const auto& snapshot : table) count += snapshot[a] && snapshot[b] ? 1 : 0;
  return count;
}

// to_from_from, and the RMS reprojection error over both cameras of every shared view.
std::pair<Eigen::Isometry3d, double> stereo_link(const CornerTable& table, size_t from, size_t to,
                                                 const std::vector<NamedIntrinsics>& cameras, const Chessboard& board) {
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> from_points, to_points;
  for (const auto& snapshot : table)
    if (snapshot[from] && snapshot[to]) {
      object_points.push_back(board.object_points());
      from_points.push_back(*snapshot[from]);
      to_points.push_back(*snapshot[to]);
    }
  const CameraIntrinsics& from_k = cameras[from].intrinsics;
  cv::Mat from_matrix = camera_matrix(from_k), from_distortion = distortion_coefficients(from_k);
  cv::Mat to_matrix = camera_matrix(cameras[to].intrinsics), to_distortion = distortion_coefficients(cameras[to].intrinsics);
  cv::Mat rotation, translation, essential, fundamental;
  double rms = 0;
  try {
    rms = cv::stereoCalibrate(object_points, from_points, to_points, from_matrix, from_distortion, to_matrix,
                              to_distortion, cv::Size(int(from_k.width), int(from_k.height)), rotation, translation,
                              essential, fundamental, cv::CALIB_FIX_INTRINSIC);
  } catch (const cv::Exception& error) {
    throw CalibrationError("cameras '" + cameras[from].name + "' and '" + cameras[to].name +
                           "': OpenCV's stereoCalibrate failed: " + error.what());
  }
  Eigen::Isometry3d to_from_from = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) to_from_from.linear()(r, c) = rotation.at<double>(r, c);
    to_from_from.translation()(r) = translation.at<double>(r);
  }
  return {to_from_from, rms};
}

}  // namespace

std::vector<CameraLink> link_cameras(const std::vector<NamedIntrinsics>& cameras,
                                     const std::vector<BoardSnapshot>& snapshots, const Chessboard& board,
                                     const std::string& reference, double max_link_rms_px) {
  const CornerTable table = tabulate(cameras, snapshots, board);
  std::vector<CameraLink> links(cameras.size());
  std::vector<bool> linked(cameras.size(), false);
  for (size_t i = 0; i < cameras.size(); ++i) {
    links[i].camera = cameras[i].name;
    if (cameras[i].name == reference) linked[i] = true;
  }
  if (std::find(linked.begin(), linked.end(), true) == linked.end())
    throw CalibrationError("the reference camera '" + reference + "' is not in the camera list");

  // Prim's algorithm on the number of shared views: each new camera joins through the linked
  // camera it saw the board with most often.
  for (size_t joined = 1; joined < cameras.size(); ++joined) {
    size_t best_from = 0, best_to = 0, best_count = 0;
    for (size_t from = 0; from < cameras.size(); ++from)
      for (size_t to = 0; to < cameras.size(); ++to)
        if (linked[from] && !linked[to])
          if (const size_t count = shared_views(table, from, to); count > best_count)
            std::tie(best_from, best_to, best_count) = std::tuple(from, to, count);
    if (best_count == 0) {
      std::string unlinked;
      for (size_t i = 0; i < cameras.size(); ++i)
        if (!linked[i]) unlinked += (unlinked.empty() ? "'" : ", '") + cameras[i].name + "'";
      throw CalibrationError("camera(s) " + unlinked + " share no chessboard view with the reference camera '" +
                             reference + "' or with a camera linked to it; take views that both see the whole board");
    }
    const auto [to_from_from, rms] = stereo_link(table, best_from, best_to, cameras, board);
    if (!to_from_from.matrix().allFinite() || !std::isfinite(rms) || rms > max_link_rms_px)
      throw CalibrationError("cameras '" + cameras[best_from].name + "' and '" + cameras[best_to].name + "': their " +
                             std::to_string(best_count) + " shared views disagree (RMS reprojection error " +
                             std::to_string(rms) + " px, at most " + std::to_string(max_link_rms_px) +
                             " px): were the views simultaneous, the intrinsics right, and the board numbered from "
                             "the same corner in both cameras?");
    CameraLink& link = links[best_to];
    link.linked_to = cameras[best_from].name;
    link.camera_from_reference = to_from_from * links[best_from].camera_from_reference;
    link.shared_views = best_count;
    link.rms_error_px = rms;
    linked[best_to] = true;
  }
  return links;
}

}  // namespace rt::calibration
