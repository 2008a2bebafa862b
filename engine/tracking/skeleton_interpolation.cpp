#include "tracking/skeleton_interpolation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt {
namespace {

// Below this a direction has no usable orientation left (parallel or zero vectors).
constexpr double kDegenerate = 1e-9;

// The palm's orientation as a rotation: columns direction, normal (made orthogonal to the
// direction), their cross product. Empty when the vectors cannot span a frame.
std::optional<Eigen::Quaterniond> palm_frame(const HandSkeleton& hand) {
  if (!hand.direction.allFinite() || !hand.palm_normal.allFinite()) return std::nullopt;
  const double direction_norm = hand.direction.norm();
  if (direction_norm < kDegenerate) return std::nullopt;
  const Eigen::Vector3d direction = hand.direction / direction_norm;
  Eigen::Vector3d normal = hand.palm_normal - direction * direction.dot(hand.palm_normal);
  const double normal_norm = normal.norm();
  if (normal_norm < kDegenerate) return std::nullopt;
  normal /= normal_norm;
  Eigen::Matrix3d frame;
  frame << direction, normal, direction.cross(normal);
  return Eigen::Quaterniond(frame);
}

const HandSkeleton* same_hand(const std::vector<HandSkeleton>& hands, const HandSkeleton& hand) {
  for (const HandSkeleton& other : hands)
    if (other.id == hand.id && other.is_left == hand.is_left) return &other;
  return nullptr;
}

}  // namespace

HandSkeleton interpolate_hand(const HandSkeleton& a, const HandSkeleton& b, double s) {
  const bool nearer_a = s < 0.5;
  const HandSkeleton& nearer = nearer_a ? a : b;
  HandSkeleton out = nearer;
  out.id = a.id;
  out.is_left = a.is_left;
  // Each joint on its own: a joint missing in either sample cannot be blended, and must not
  // reach the others.
  auto lerp = [s](const Eigen::Vector3d& pa, const Eigen::Vector3d& pb, const Eigen::Vector3d& fallback) {
    return pa.allFinite() && pb.allFinite() ? Eigen::Vector3d(pa + s * (pb - pa)) : fallback;
  };
  out.wrist = lerp(a.wrist, b.wrist, nearer.wrist);
  out.palm = lerp(a.palm, b.palm, nearer.palm);
  out.elbow = lerp(a.elbow, b.elbow, nearer.elbow);
  for (size_t d = 0; d < out.digits.size(); ++d)
    for (size_t j = 0; j < out.digits[d].size(); ++j) out.digits[d][j] = lerp(a.digits[d][j], b.digits[d][j], nearer.digits[d][j]);
  if (std::isfinite(a.confidence) && std::isfinite(b.confidence))
    out.confidence = float(double(a.confidence) + s * (double(b.confidence) - double(a.confidence)));
  out.timestamp_us = uint64_t(double(a.timestamp_us) + s * (double(b.timestamp_us) - double(a.timestamp_us)) + 0.5);
  // The palm turns as a rigid frame: slerping the two vectors apart would let them drift off
  // perpendicular and off the rotation the hand made.
  const auto frame_a = palm_frame(a), frame_b = palm_frame(b);
  if (frame_a && frame_b) {
    const Eigen::Quaterniond frame = frame_a->slerp(s, *frame_b);
    const Eigen::Matrix3d rotation = frame.toRotationMatrix();
    out.direction = rotation.col(0);
    out.palm_normal = rotation.col(1);
  }
  return out;
}

HandsAtTime hands_at(std::span<const SkeletonSample> samples, uint64_t t_us, uint64_t max_gap_us) {
  for (size_t i = 1; i < samples.size(); ++i)
    if (samples[i].timestamp_us < samples[i - 1].timestamp_us)
      throw std::invalid_argument("hands_at: the skeleton samples are not in time order");
  HandsAtTime result;
  result.max_gap_us = max_gap_us;
  if (samples.empty()) return result;
  const auto after = std::lower_bound(samples.begin(), samples.end(), t_us,
                                      [](const SkeletonSample& sample, uint64_t t) { return sample.timestamp_us < t; });
  const SkeletonSample* b = after != samples.end() ? &*after : nullptr;       // at or after t
  const SkeletonSample* a = after != samples.begin() ? &*(after - 1) : nullptr;  // before t
  const uint64_t gap_a = a ? t_us - a->timestamp_us : UINT64_MAX;
  const uint64_t gap_b = b ? b->timestamp_us - t_us : UINT64_MAX;
  const bool a_nearer = gap_a <= gap_b;
  const SkeletonSample& nearer = a_nearer ? *a : *b;
  const SkeletonSample* farther = a_nearer ? b : a;
  const uint64_t nearer_gap = std::min(gap_a, gap_b);
  result.nearest_sample_gap_us = nearer_gap;
  if (nearer_gap > max_gap_us) return result;  // stale: nothing known about this moment
  const bool bracketed = farther && nearer_gap > 0 && std::max(gap_a, gap_b) <= max_gap_us;
  for (const HandSkeleton& hand : nearer.hands) {
    const HandSkeleton* other = bracketed ? same_hand(farther->hands, hand) : nullptr;
    if (other) {
      const HandSkeleton& before = a_nearer ? hand : *other;
      const HandSkeleton& later = a_nearer ? *other : hand;
      const double s = double(gap_a) / double(b->timestamp_us - a->timestamp_us);
      HandSkeleton at = interpolate_hand(before, later, s);
      at.timestamp_us = t_us;
      result.hands.push_back(std::move(at));
      result.gap_us.push_back(std::max(gap_a, gap_b));
      result.interpolated.push_back(true);
    } else {
      HandSkeleton held = hand;
      held.timestamp_us = nearer.timestamp_us;
      result.hands.push_back(std::move(held));
      result.gap_us.push_back(nearer_gap);
      result.interpolated.push_back(false);
    }
  }
  return result;
}

SkeletonHistory::SkeletonHistory(size_t capacity, uint64_t max_gap_us)
    : capacity_(capacity == 0 ? 1 : capacity), max_gap_us_(max_gap_us) {}

void SkeletonHistory::add(SkeletonSample sample) {
  std::lock_guard lock(mutex_);
  const auto at = std::lower_bound(samples_.begin(), samples_.end(), sample.timestamp_us,
                                   [](const SkeletonSample& kept, uint64_t t) { return kept.timestamp_us < t; });
  if (at != samples_.end() && at->timestamp_us == sample.timestamp_us) {
    *at = std::move(sample);
    return;
  }
  if (samples_.size() >= capacity_ && at == samples_.begin()) return;  // older than all kept
  samples_.insert(at, std::move(sample));
  if (samples_.size() > capacity_) samples_.erase(samples_.begin(), samples_.begin() + ptrdiff_t(samples_.size() - capacity_));
}

HandsAtTime SkeletonHistory::at(uint64_t t_us) const {
  std::lock_guard lock(mutex_);
  return hands_at(samples_, t_us, max_gap_us_);
}

size_t SkeletonHistory::size() const {
  std::lock_guard lock(mutex_);
  return samples_.size();
}

}  // namespace rt
