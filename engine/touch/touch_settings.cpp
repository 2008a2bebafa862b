#include "touch/touch_settings.h"

namespace rt {

const config::KnobTable<TouchSettings>& touch_knobs() {
  using S = TouchSettings;
  using config::KnobKind;
  static const config::KnobTable<S> table = {
      {"contact-prediction",
       "Pulse the motor ahead of the palms' predicted contact by its latency, so that it vibrates as they meet (off: "
       "when the touch is detected, which is after it)",
       KnobKind::Choice, 0, 0, {"on", "off"}, [](const S& s) { return s.contact_prediction ? 0.0 : 1.0; },
       [](S& s, double v) { s.contact_prediction = v == 0; }},
      {"motor-latency-ms", "From the motor command to the vibration felt (the simulated motor's spin-up)", KnobKind::Real,
       0, 1000, {}, [](const S& s) { return s.motor_latency_ms; }, [](S& s, double v) { s.motor_latency_ms = v; }},
  };
  return table;
}

nlohmann::json touch_settings_json(const TouchSettings& settings) { return config::knobs_to_json(touch_knobs(), settings); }

}  // namespace rt
