#include "viewer/initial_viewpoint.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rt {

namespace {

double median(std::vector<double> values) {
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(middle), values.end());
  const double upper = values[middle];
  if (values.size() % 2 == 1) return upper;
  return (upper + *std::max_element(values.begin(), values.begin() + std::ptrdiff_t(middle))) / 2.0;
}

}  // namespace

InitialViewpointEstimator::InitialViewpointEstimator(const InitialViewpointOptions& options) : options_(options) {
  if (options.frames_needed < 1) throw std::invalid_argument("InitialViewpointOptions::frames_needed must be >= 1");
  if (!(options.outlier_distance_m > 0 && options.max_spread_m > 0))
    throw std::invalid_argument("InitialViewpointOptions: outlier_distance_m and max_spread_m must be > 0");
}

void InitialViewpointEstimator::add(uint64_t timestamp_us, const EyePair& frame) {
  // triangulate_eye_pair never returns a non-finite success, but a hand-made EyePair might.
  if (!frame.ok() || !frame.midpoint.allFinite() || !(frame.midpoint.z() > 0.0)) {
    ++frames_without_eyes_;
    return;
  }
  samples_.push_back({timestamp_us, frame.midpoint});
}

InitialViewpoint InitialViewpointEstimator::result() const {
  InitialViewpoint result;
  result.frames_without_eyes = frames_without_eyes_;
  if (samples_.size() < options_.frames_needed) {
    result.failure = ViewerFailure::TooFewFrames;
    result.message = "the eyes were seen in " + std::to_string(samples_.size()) + " frame(s) of " +
                     std::to_string(samples_.size() + frames_without_eyes_) + ", " + std::to_string(options_.frames_needed) +
                     " are needed";
    return result;
  }
  // The per-axis median ignores up to half the frames being wrong, whatever their error.
  Eigen::Vector3d centre;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (const Sample& sample : samples_) values.push_back(sample.midpoint[axis]);
    centre[axis] = median(values);
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Sample& sample : samples_) {
    if ((sample.midpoint - centre).norm() > options_.outlier_distance_m) {
      ++result.frames_outliers;
      continue;
    }
    sum += sample.midpoint;
    ++result.frames_used;
    result.timestamp_us = std::max(result.timestamp_us, sample.timestamp_us);
  }
  if (result.frames_used < options_.frames_needed) {
    result.failure = ViewerFailure::TooFewFrames;
    result.message = std::to_string(result.frames_used) + " frame(s) agree within " +
                     std::to_string(int(std::lround(options_.outlier_distance_m * 1000))) + " mm (" +
                     std::to_string(result.frames_outliers) + " outliers), " + std::to_string(options_.frames_needed) +
                     " are needed";
    return result;
  }
  // The mean of the agreeing frames averages their noise down, which the median would not.
  result.midpoint = sum / double(result.frames_used);
  double squared = 0.0;
  for (const Sample& sample : samples_)
    if ((sample.midpoint - centre).norm() <= options_.outlier_distance_m) squared += (sample.midpoint - result.midpoint).squaredNorm();
  result.spread_m = std::sqrt(squared / double(result.frames_used));
  if (result.spread_m > options_.max_spread_m) {
    std::ostringstream message;
    message << "the frames' viewpoints spread by " << result.spread_m * 1000.0 << " mm RMS, more than "
            << options_.max_spread_m * 1000.0 << " mm: the viewer is moving, use the continuous tracker";
    result.failure = ViewerFailure::Unsteady;
    result.message = message.str();
  }
  return result;
}

}  // namespace rt
