#include "touch/site_touch_loop.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/tracker_sim.h"
#include "touch/scene_contact.h"

namespace rt {
namespace {

void check_time_scale(double time_scale) {
  if (!std::isfinite(time_scale) || time_scale <= 0)
    throw std::invalid_argument("site touch loop: the time scale must be positive");
}

uint64_t slowed(uint64_t us, double time_scale) { return uint64_t(std::llround(double(us) / time_scale)); }

}  // namespace

TouchParameters site_touch_parameters(double time_scale) {
  check_time_scale(time_scale);
  TouchParameters touch = hand_mesh_touch_parameters();
  touch.max_skeleton_age_us = 200'000 + slowed(sim::kTrackerPeriodUs, time_scale);
  touch.touch_hold_age_us = 1'000'000;
  touch.dropout_hold_us = std::min(touch.touch_hold_age_us, slowed(touch.dropout_hold_us, time_scale));
  return touch;
}

MotorTiming site_motor_timing(const TouchSettings& settings, double time_scale) {
  check_time_scale(time_scale);
  if (!std::isfinite(settings.motor_latency_ms) || settings.motor_latency_ms < 0)
    throw std::invalid_argument("the motor's latency must be a number of milliseconds >= 0");
  MotorTiming timing;
  timing.predict = settings.contact_prediction;
  timing.motor_spin_up_us = uint64_t(std::llround(settings.motor_latency_ms * 1000.0));
  // The detector sees a contact a tracker frame, a tick and the link's delay after it; a tracker
  // frame stands longer where the scene plays slowly.
  timing.confirm_window_us = slowed(timing.confirm_window_us, std::min(time_scale, 1.0));
  ContactPredictionParameters prediction;
  prediction.contact_height_m = kPalmMetHeightM;
  timing.prediction = scaled_to_time(prediction, time_scale);
  return timing;
}

SiteTouchLoop::SiteTouchLoop(const TouchSettings& settings, double time_scale, TouchLoop::EventHandler on_event,
                             TouchLoop::MotorHandler on_motor)
    : timing_(site_motor_timing(settings, time_scale)),
      loop_(site_touch_parameters(time_scale), std::move(on_event), std::chrono::microseconds(20'000), timing_,
            std::move(on_motor)) {}

void SiteTouchLoop::set_local_hands(std::vector<HandSkeleton> hands) { loop_.set_local_hands(std::move(hands)); }

uint64_t SiteTouchLoop::set_remote_hands(std::vector<HandSkeleton> hands, uint64_t remote_stamp_us, uint64_t arrival_us) {
  const uint64_t local_us = remote_clock_.to_local(remote_stamp_us, arrival_us);
  for (HandSkeleton& hand : hands) hand.timestamp_us = local_us;
  loop_.set_remote_hands(std::move(hands));
  return local_us;
}

}  // namespace rt
