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

// The scene times (s) at which the users' true hands meet: both hands' joints within
// kPalmMetHeightM of the glass, their boxes on it overlapping by the detector's start area
// (mutual_touch.h), sampled every millisecond in site A's frame. A meeting ends once the overlap
// falls under the end area.
std::vector<double> true_contact_times_s(const sim::Scene& scene, const TouchParameters& touch = {});

// Each true contact (µs, the site's clock) with the first vibration felt within `window_us` of
// it, its error (felt - contact, ms; null where none was felt), their median and largest
// magnitude, and the vibrations felt near no contact.
nlohmann::json contact_to_vibration_json(const std::vector<uint64_t>& contacts_us, const std::vector<uint64_t>& felt_us,
                                         uint64_t window_us);

}  // namespace rt
