#pragma once
// A site's touch knobs (config/knobs.h): the command-line options --contact-prediction and
// --motor-latency-ms, a site config's "touch" object, and what the demo forwards to each site.
// A new knob is one field of TouchSettings plus one row in touch_knobs() (touch_settings.cpp).
#include <nlohmann/json.hpp>

#include "config/knobs.h"

namespace rt {

struct TouchSettings {
  // The motor is told ahead of the predicted contact by its latency (touch_loop.h's MotorTiming);
  // off: when the detector sees the touch, which is after it. On by default: docs/touch-on-time.md
  // has the figures that chose it.
  bool contact_prediction = true;
  // From the motor command to the vibration a hand feels; the simulated motor models it as its
  // spin-up.
  double motor_latency_ms = 60.0;
};

// contact-prediction (on|off), motor-latency-ms.
const config::KnobTable<TouchSettings>& touch_knobs();

// Every knob of `settings` as JSON (keys as in a site config's "touch" object), for metrics files.
nlohmann::json touch_settings_json(const TouchSettings& settings);

}  // namespace rt
