#include "touch/scene_contact.h"

#include <algorithm>
#include <cmath>

#include "geometry/site_frames.h"

namespace rt {

std::vector<double> true_contact_times_s(const sim::Scene& scene, const TouchParameters& touch) {
  const sim::MotionTrack a = sim::make_motion_track(scene, Site::A), b = sim::make_motion_track(scene, Site::B);
  constexpr double kStepS = 0.001;
  std::vector<double> starts;
  bool met = false;
  const int64_t steps = int64_t(std::ceil(scene.duration_s() / kStepS));
  for (int64_t i = 0; i <= steps; ++i) {
    const double t = double(i) * kStepS;
    const sim::PersonPose pa = a.pose_at(t), pb = b.pose_at(t);
    const HandSkeleton local[] = {pa.right_hand, pa.left_hand};
    const HandSkeleton remote[] = {map_skeleton(Site::B, Site::A, pb.right_hand), map_skeleton(Site::B, Site::A, pb.left_hand)};
    const double area = overlap_area_m2(local, remote, kPalmMetHeightM);
    if (!met && area > touch.start_area_m2) {
      met = true;
      starts.push_back(t);
    } else if (met && area < touch.end_area_m2) {
      met = false;
    }
  }
  return starts;
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
