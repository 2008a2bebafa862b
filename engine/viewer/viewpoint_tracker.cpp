#include "viewer/viewpoint_tracker.h"

#include <cmath>
#include <stdexcept>

namespace rt {

const char* verdict_name(TrackerVerdict verdict) {
  switch (verdict) {
    case TrackerVerdict::Started: return "started";
    case TrackerVerdict::Accepted: return "accepted";
    case TrackerVerdict::Reacquired: return "reacquired";
    case TrackerVerdict::RejectedJump: return "rejected: jump";
    case TrackerVerdict::RejectedReprojection: return "rejected: reprojection";
    case TrackerVerdict::RejectedInvalid: return "rejected: invalid";
    case TrackerVerdict::NotFound: return "not found";
    case TrackerVerdict::IgnoredOutOfOrder: return "ignored: out of order";
    case TrackerVerdict::IgnoredDuplicate: return "ignored: duplicate";
  }
  return "unknown";
}

ViewpointTracker::ViewpointTracker(const ViewpointTrackerOptions& options) : options_(options), filter_(options.smoothing) {
  if (!(options.max_speed_m_per_s > 0 && options.jump_allowance_m >= 0 && options.max_reprojection_mrad > 0) ||
      !std::isfinite(options.max_speed_m_per_s + options.jump_allowance_m + options.max_reprojection_mrad))
    throw std::invalid_argument("ViewpointTrackerOptions: max_speed and max_reprojection must be > 0, jump_allowance >= 0");
  if (options.reacquire_after < 2) throw std::invalid_argument("ViewpointTrackerOptions::reacquire_after must be >= 2");
}

bool ViewpointTracker::timestamp_is_new(uint64_t timestamp_us, TrackerVerdict& ignored) {
  if (newest_timestamp_us_ && timestamp_us <= *newest_timestamp_us_) {
    ignored = timestamp_us == *newest_timestamp_us_ ? TrackerVerdict::IgnoredDuplicate : TrackerVerdict::IgnoredOutOfOrder;
    return false;
  }
  newest_timestamp_us_ = timestamp_us;
  return true;
}

double ViewpointTracker::gate_m(uint64_t from_us, uint64_t to_us) const {
  return options_.max_speed_m_per_s * double(to_us - from_us) * 1e-6 + options_.jump_allowance_m;
}

TrackerVerdict ViewpointTracker::update(uint64_t timestamp_us, const EyePair& measurement) {
  if (!measurement.ok()) {
    TrackerVerdict ignored;
    if (!timestamp_is_new(timestamp_us, ignored)) return ignored;
    return TrackerVerdict::NotFound;
  }
  return update(timestamp_us, measurement.midpoint, measurement.max_reprojection_mrad);
}

TrackerVerdict ViewpointTracker::update(uint64_t timestamp_us, const Eigen::Vector3d& midpoint, double reprojection_mrad) {
  TrackerVerdict ignored;
  if (!timestamp_is_new(timestamp_us, ignored)) return ignored;
  if (!midpoint.allFinite() || !std::isfinite(reprojection_mrad) || reprojection_mrad < 0 ||
      !(midpoint.z() > options_.min_distance_to_screen_m))
    return TrackerVerdict::RejectedInvalid;
  if (reprojection_mrad > options_.max_reprojection_mrad) return TrackerVerdict::RejectedReprojection;

  if (!filter_.initialised()) {
    filter_.reset(midpoint);
    accepted_timestamp_us_ = timestamp_us;
    return TrackerVerdict::Started;
  }
  if ((midpoint - filter_.value()).norm() > gate_m(accepted_timestamp_us_, timestamp_us)) {
    // A run of rejections that are consistent among themselves is the viewer, not noise.
    if (!rejected_run_.empty() &&
        (midpoint - rejected_run_.back().midpoint).norm() > gate_m(rejected_run_.back().timestamp_us, timestamp_us))
      rejected_run_.clear();
    rejected_run_.push_back({timestamp_us, midpoint});
    if (rejected_run_.size() < options_.reacquire_after) return TrackerVerdict::RejectedJump;
    filter_.reset(midpoint);
    accepted_timestamp_us_ = timestamp_us;
    rejected_run_.clear();
    return TrackerVerdict::Reacquired;
  }
  filter_.update(midpoint, double(timestamp_us - accepted_timestamp_us_) * 1e-6);
  accepted_timestamp_us_ = timestamp_us;
  rejected_run_.clear();
  return TrackerVerdict::Accepted;
}

std::optional<TrackedViewpoint> ViewpointTracker::latest() const {
  if (!filter_.initialised()) return std::nullopt;
  return TrackedViewpoint{filter_.value(), filter_.velocity(), accepted_timestamp_us_};
}

bool ViewpointTracker::lost(uint64_t now_us, uint64_t timeout_us) const {
  if (!filter_.initialised()) return true;
  return now_us < accepted_timestamp_us_ ? false : now_us - accepted_timestamp_us_ > timeout_us;
}

}  // namespace rt
