#include "touch/scene_contact.h"

#include <algorithm>
#include <cmath>

#include "geometry/site_frames.h"

namespace rt {

std::vector<TrueContact> true_contacts(const sim::Scene& scene, const TouchParameters& touch) {
  const sim::MotionTrack a = sim::make_motion_track(scene, Site::A), b = sim::make_motion_track(scene, Site::B);
  TouchParameters exact = touch;
  exact.joint_distance_m = kPalmMetHeightM;
  exact.mesh.band_m = kRestingSkinBandM;
  // Under the hand meshes, only hands come to rest on the glass take part.
  auto resting = [&](std::vector<HandSkeleton> hands, double side) {
    if (touch.rule != TouchRule::HandMeshes) return hands;
    std::erase_if(hands, [&](const HandSkeleton& hand) {
      for (const Eigen::Vector3d& joint : hand.hand_joints())
        if (side * joint.z() <= kPalmMetHeightM) return false;
      return true;
    });
    return hands;
  };
  constexpr double kStepS = 0.001;
  std::vector<TrueContact> starts;
  bool met = false;
  const int64_t steps = int64_t(std::ceil(scene.duration_s() / kStepS));
  for (int64_t i = 0; i <= steps; ++i) {
    const double t = double(i) * kStepS;
    const sim::PersonPose pa = a.pose_at(t), pb = b.pose_at(t);
    const std::vector<HandSkeleton> local = resting({pa.right_hand, pa.left_hand}, 1.0);
    const std::vector<HandSkeleton> remote =
        resting({map_skeleton(Site::B, Site::A, pb.right_hand), map_skeleton(Site::B, Site::A, pb.left_hand)}, -1.0);
    const MeshContact contact = touch_overlap(local, remote, exact);
    if (!met && contact.overlap_area_m2 > exact.start_area_m2) {
      met = true;
      starts.push_back({t, contact.gesture});
    } else if (met && contact.overlap_area_m2 < exact.end_area_m2) {
      met = false;
    }
  }
  return starts;
}

std::vector<double> true_contact_times_s(const sim::Scene& scene, const TouchParameters& touch) {
  std::vector<double> times;
  for (const TrueContact& contact : true_contacts(scene, touch)) times.push_back(contact.t_s);
  return times;
}

nlohmann::json contact_to_vibration_json(const std::vector<uint64_t>& contacts_us, const std::vector<uint64_t>& felt_us,
                                         uint64_t window_us) {
  auto near = [&](uint64_t felt, uint64_t contact) {
    return felt + window_us >= contact && felt <= contact + window_us;
  };
  nlohmann::json touches = nlohmann::json::array();
  std::vector<double> errors_ms;
  for (const uint64_t contact : contacts_us) {
    nlohmann::json touch = {{"contact_us", contact}, {"error_ms", nullptr}};
    for (const uint64_t felt : felt_us)
      if (near(felt, contact)) {
        const double error = (double(felt) - double(contact)) / 1000.0;
        touch["error_ms"] = error;
        errors_ms.push_back(error);
        break;
      }
    touches.push_back(touch);
  }
  uint64_t stray = 0;
  for (const uint64_t felt : felt_us)
    if (std::none_of(contacts_us.begin(), contacts_us.end(), [&](uint64_t contact) { return near(felt, contact); }))
      ++stray;
  nlohmann::json out = {{"touches", touches},
                        {"contacts", contacts_us.size()},
                        {"contacts_not_felt", contacts_us.size() - errors_ms.size()},
                        {"vibrations_without_contact", stray},
                        {"median_ms", nullptr},
                        {"abs_max_ms", nullptr}};
  if (!errors_ms.empty()) {
    std::vector<double> sorted = errors_ms;
    std::sort(sorted.begin(), sorted.end());
    out["median_ms"] = sorted[sorted.size() / 2];
    double largest = 0;
    for (const double e : errors_ms) largest = std::max(largest, std::abs(e));
    out["abs_max_ms"] = largest;
  }
  return out;
}

}  // namespace rt
