#pragma once
// When the palms truly meet in a simulated scene, and how far from it each vibration a site's
// motor gave was felt: the truth that contact prediction (touch_loop.h) is measured against.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "sim/motion.h"
#include "sim/scene.h"
#include "touch/mutual_touch.h"

namespace rt {

// A palm meets the glass when its joints are within a millimetre of where they rest on it: the
// skeleton runs half a centimetre above the skin of a flat palm (sim::kTouchPalmHeightM).
inline constexpr double kPalmMetHeightM = sim::kTouchPalmHeightM + 0.001;
// Skin this close to the glass is where a hand rests on it: the part of the hand that touches.
inline constexpr double kRestingSkinBandM = 0.004;

// The scene times (s) at which the users' true hands meet, sampled every millisecond in site A's
// frame, by the rule of `touch` (mutual_touch.h) made exact: under the joint boxes, both hands'
// joints within kPalmMetHeightM of the glass, their boxes overlapping by the start area; under
// the hand meshes, both hands' nearest joints within kPalmMetHeightM of it (a hand that has come
// to rest on the glass: the scenes rest a palm's, a fist's knuckles' and a fingertip's joints at
// most that far out) and their skin within kRestingSkinBandM of it overlapping by the start area. The template's skin is
// thicker than the simulated hand, so the skin alone would meet before the hands do. A meeting
// ends once the overlap falls under the end area.
struct TrueContact {
  double t_s = 0.0;
  Gesture gesture = Gesture::Palm;
};
std::vector<TrueContact> true_contacts(const sim::Scene& scene, const TouchParameters& touch);
// The contacts' times under the hand-mesh rule, as the sites detect touches.
std::vector<double> true_contact_times_s(const sim::Scene& scene,
                                         const TouchParameters& touch = hand_mesh_touch_parameters());

// Each true contact (µs, the site's clock) with the first vibration felt within `window_us` of
// it, its error (felt - contact, ms; null where none was felt), their median and largest
// magnitude, and the vibrations felt near no contact.
nlohmann::json contact_to_vibration_json(const std::vector<uint64_t>& contacts_us, const std::vector<uint64_t>& felt_us,
                                         uint64_t window_us);

}  // namespace rt
