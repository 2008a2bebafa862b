#include "touch/mutual_touch.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rt {
namespace {

// Hands whose capture time is recent enough; stale ones count as lost tracking.
std::vector<HandSkeleton> fresh(std::span<const HandSkeleton> hands, uint64_t now_us, uint64_t max_age_us,
                                uint64_t& newest_capture_us) {
  std::vector<HandSkeleton> result;
  for (const HandSkeleton& hand : hands) {
    if (hand.timestamp_us + max_age_us < now_us) continue;
    newest_capture_us = std::max(newest_capture_us, hand.timestamp_us);
    result.push_back(hand);
  }
  return result;
}

}  // namespace

void check_touch_parameters(const TouchParameters& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("touch parameters: " + what); };
  if (!(p.joint_distance_m > 0.0) || !std::isfinite(p.joint_distance_m)) fail("joint_distance_m must be > 0");
  if (!(p.start_area_m2 > 0.0) || !std::isfinite(p.start_area_m2)) fail("start_area_m2 must be > 0");
  if (!(p.end_area_m2 >= 0.0) || p.end_area_m2 > p.start_area_m2) fail("end_area_m2 must be in [0, start_area_m2]");
  if (p.end_after_ticks < 1) fail("end_after_ticks must be at least 1");
  if (p.max_skeleton_age_us == 0) fail("max_skeleton_age_us must be > 0");
  if (p.touch_hold_age_us < p.max_skeleton_age_us) fail("touch_hold_age_us must be >= max_skeleton_age_us");
  if (p.dropout_hold_us > p.touch_hold_age_us) fail("dropout_hold_us must be <= touch_hold_age_us");
  check_mesh_contact_parameters(p.mesh);
}

TouchParameters hand_mesh_touch_parameters() {
  TouchParameters p;
  p.rule = TouchRule::HandMeshes;
  p.start_area_m2 = 1e-4;
  p.end_area_m2 = 0.25e-4;
  return p;
}

MeshContact touch_overlap(std::span<const HandSkeleton> local_hands, std::span<const HandSkeleton> remote_hands,
                          const TouchParameters& parameters, ContactPatchCache* cache) {
  if (parameters.rule == TouchRule::HandMeshes) return mesh_contact(local_hands, remote_hands, parameters.mesh, cache);
  return {overlap_area_m2(local_hands, remote_hands, parameters.joint_distance_m), Gesture::Palm};
}

std::optional<Eigen::AlignedBox2d> contact_box(const HandSkeleton& hand, double joint_distance_m) {
  Eigen::AlignedBox2d box;  // empty
  bool any = false;
  for (const Eigen::Vector3d& joint : hand.hand_joints()) {
    if (!joint.allFinite() || std::abs(joint.z()) > joint_distance_m) continue;
    box.extend(joint.head<2>());
    any = true;
  }
  if (!any) return std::nullopt;
  return box;
}

double overlap_area_m2(std::span<const HandSkeleton> local_hands, std::span<const HandSkeleton> remote_hands,
                       double joint_distance_m) {
  double best = 0.0;
  for (const HandSkeleton& local : local_hands) {
    const auto local_box = contact_box(local, joint_distance_m);
    if (!local_box) continue;
    for (const HandSkeleton& remote : remote_hands) {
      const auto remote_box = contact_box(remote, joint_distance_m);
      if (!remote_box || !local_box->intersects(*remote_box)) continue;
      const Eigen::Vector2d size = local_box->intersection(*remote_box).sizes();
      best = std::max(best, size.x() * size.y());
    }
  }
  return best;
}

const char* touch_event_name(TouchEvent::Kind kind) { return kind == TouchEvent::Kind::Start ? "touch-start" : "touch-end"; }

MutualTouchDetector::MutualTouchDetector(const TouchParameters& parameters) : parameters_(parameters) {
  check_touch_parameters(parameters_);
}

std::optional<TouchEvent> MutualTouchDetector::update(uint64_t now_us, std::span<const HandSkeleton> local_hands,
                                                      std::span<const HandSkeleton> remote_hands) {
  TouchEvent event;
  event.timestamp_us = now_us;
  const uint64_t max_age_us = touching_ ? parameters_.touch_hold_age_us : parameters_.max_skeleton_age_us;
  // During a touch, a side without hands stands on its last ones through a short dropout.
  auto held = [&](std::span<const HandSkeleton> hands, std::vector<HandSkeleton>& last) {
    if (!hands.empty()) {
      last.assign(hands.begin(), hands.end());
      return std::vector<HandSkeleton>(hands.begin(), hands.end());
    }
    std::vector<HandSkeleton> standing;
    if (touching_)
      for (const HandSkeleton& hand : last)
        if (hand.timestamp_us + parameters_.dropout_hold_us >= now_us) standing.push_back(hand);
    return standing;
  };
  const auto local = fresh(held(local_hands, last_local_), now_us, max_age_us, event.local_capture_us);
  const auto remote = fresh(held(remote_hands, last_remote_), now_us, max_age_us, event.remote_capture_us);
  const MeshContact contact = touch_overlap(local, remote, parameters_, &patch_cache_);
  event.overlap_area_m2 = contact.overlap_area_m2;
  event.gesture = touching_ ? gesture_ : contact.gesture;

  if (!touching_) {
    if (event.overlap_area_m2 > parameters_.start_area_m2) {
      touching_ = true;
      gesture_ = contact.gesture;
      ticks_below_end_ = 0;
      event.kind = TouchEvent::Kind::Start;
      return event;
    }
    return std::nullopt;
  }
  ticks_below_end_ = event.overlap_area_m2 < parameters_.end_area_m2 ? ticks_below_end_ + 1 : 0;
  if (ticks_below_end_ >= parameters_.end_after_ticks) {
    touching_ = false;
    ticks_below_end_ = 0;
    event.kind = TouchEvent::Kind::End;
    return event;
  }
  return std::nullopt;
}

}  // namespace rt
