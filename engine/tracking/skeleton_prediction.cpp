#include "tracking/skeleton_prediction.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace rt {
namespace {

struct Motion {
  Eigen::Vector3d at_newest = Eigen::Vector3d::Zero();  // the fitted position at the newest sample
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
};

// Least squares of p(t) = p0 + v t + a t^2 / 2 over the samples (t <= 0, seconds, the newest at
// 0). Two samples give a velocity only; one gives no motion.
Motion fit_motion(const std::vector<std::pair<double, Eigen::Vector3d>>& samples) {
  Motion motion;
  motion.at_newest = samples.back().second;
  if (samples.size() < 2) return motion;
  const Eigen::Index columns = samples.size() == 2 ? 2 : 3;
  Eigen::MatrixXd basis(samples.size(), columns);
  Eigen::MatrixXd positions(samples.size(), 3);
  for (size_t i = 0; i < samples.size(); ++i) {
    const double t = samples[i].first;
    basis(Eigen::Index(i), 0) = 1.0;
    basis(Eigen::Index(i), 1) = t;
    if (columns == 3) basis(Eigen::Index(i), 2) = 0.5 * t * t;
    positions.row(Eigen::Index(i)) = samples[i].second.transpose();
  }
  const Eigen::MatrixXd fit = basis.colPivHouseholderQr().solve(positions);
  if (!fit.allFinite()) return motion;
  motion.at_newest = fit.row(0).transpose();
  motion.velocity = fit.row(1).transpose();
  if (columns == 3) motion.acceleration = fit.row(2).transpose();
  return motion;
}

Eigen::Vector3d clamp_norm(const Eigen::Vector3d& v, double max) {
  const double n = v.norm();
  return n > max ? Eigen::Vector3d(v * (max / n)) : v;
}

// Every joint of the hand, the elbow too, for the loops that treat them alike.
template <class Hand, class Visit>
void for_each_joint(Hand& hand, Visit visit) {
  visit(hand.wrist);
  visit(hand.palm);
  visit(hand.elbow);
  for (auto& digit : hand.digits)
    for (auto& joint : digit) visit(joint);
}

}  // namespace

void check_skeleton_prediction_parameters(const SkeletonPredictionParameters& p) {
  auto require = [](bool ok, const std::string& why) {
    if (!ok) throw std::invalid_argument("skeleton prediction: " + why);
  };
  require(p.history_us > 0, "the history must be positive");
  require(p.acceleration_fade_us > 0, "the acceleration's fade must be positive");
  require(std::isfinite(p.max_speed_m_s) && p.max_speed_m_s >= 0, "the speed limit must be >= 0");
  require(std::isfinite(p.min_speed_m_s) && p.min_speed_m_s >= 0, "the least speed must be >= 0");
  require(std::isfinite(p.max_acceleration_m_s2) && p.max_acceleration_m_s2 >= 0, "the acceleration limit must be >= 0");
}

std::optional<HandSkeleton> predict_hand(std::span<const HandSkeleton> history, uint64_t at_us,
                                         const SkeletonPredictionParameters& parameters) {
  check_skeleton_prediction_parameters(parameters);
  if (history.empty()) return std::nullopt;
  const HandSkeleton& newest = history.back();
  HandSkeleton predicted = newest;
  const uint64_t lead_us = at_us > newest.timestamp_us ? at_us - newest.timestamp_us : 0;
  const double lead_s = double(std::min(lead_us, parameters.max_lead_us)) * 1e-6;
  predicted.timestamp_us = std::max(at_us, newest.timestamp_us);
  // The acceleration fades as exp(-s / fade): the position it adds over the lead.
  const double fade_s = double(parameters.acceleration_fade_us) * 1e-6;
  const double accelerated = fade_s * (lead_s - fade_s * (1.0 - std::exp(-lead_s / fade_s)));
  size_t first = history.size() - 1;
  while (first > 0 && history[first - 1].timestamp_us + parameters.history_us >= newest.timestamp_us &&
         history[first - 1].timestamp_us < history[first].timestamp_us)
    --first;
  const std::span<const HandSkeleton> window = history.subspan(first);

  // The hand moves as a whole: its centre, the mean of many joints, averages the tracker's noise
  // on each, where a fit of each joint alone turned that noise into metres per second. The centre
  // is taken over the joints that every sample of the window has, so that a joint a sample lacks
  // does not move it.
  std::vector<bool> common;
  for_each_joint(newest, [&](const Eigen::Vector3d& joint) { common.push_back(joint.allFinite()); });
  for (const HandSkeleton& sample : window) {
    size_t index = 0;
    for_each_joint(sample, [&](const Eigen::Vector3d& joint) {
      if (!joint.allFinite()) common[index] = false;
      ++index;
    });
  }
  std::vector<std::pair<double, Eigen::Vector3d>> centres;
  for (const HandSkeleton& sample : window) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    size_t index = 0;
    for_each_joint(sample, [&](const Eigen::Vector3d& joint) {
      if (common[index++]) sum += joint, ++count;
    });
    if (count > 0) centres.emplace_back((double(sample.timestamp_us) - double(newest.timestamp_us)) * 1e-6, sum / count);
  }
  if (centres.empty() || centres.back().first != 0.0) {
    for_each_joint(predicted, [](Eigen::Vector3d& joint) {
      if (joint.allFinite()) joint.z() = std::max(joint.z(), 0.0);
    });
    return predicted;
  }
  Motion motion = fit_motion(centres);
  if (motion.velocity.norm() < parameters.min_speed_m_s) motion = Motion{centres.back().second};
  motion.velocity = clamp_norm(motion.velocity, parameters.max_speed_m_s);
  motion.acceleration = clamp_norm(motion.acceleration, parameters.max_acceleration_m_s2);
  Eigen::Vector3d step = motion.at_newest - centres.back().second;
  for (int k = 0; k < 3; ++k) {
    const double v = motion.velocity(k), a = motion.acceleration(k);
    if (v * a < 0) {
      // Slowing down: it comes to a stop and stays there, rather than turning back.
      const double t = std::min(lead_s, -v / a);
      step(k) += v * t + 0.5 * a * t * t;
    } else {
      step(k) += v * lead_s + a * accelerated;
    }
  }
  step = clamp_norm(step, parameters.max_speed_m_s * std::max(lead_s, 1e-3));
  // Never through the glass (the user's side of it is z >= 0): the hand stops where its nearest
  // joint meets it, and a joint the tracker put behind it is put back on it.
  double lowest = std::numeric_limits<double>::infinity();
  for_each_joint(newest, [&](const Eigen::Vector3d& joint) {
    if (joint.allFinite()) lowest = std::min(lowest, joint.z());
  });
  if (std::isfinite(lowest)) step.z() = std::max(step.z(), -std::max(lowest, 0.0));
  for_each_joint(predicted, [&](Eigen::Vector3d& joint) {
    if (!joint.allFinite()) return;
    joint += step;
    joint.z() = std::max(joint.z(), 0.0);
  });
  return predicted;
}

}  // namespace rt
