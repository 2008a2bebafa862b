#pragma once
// The touch loop as a site runs it (site/site_run.cpp), on the CPU so that a test can drive it
// on a simulated clock: the detector's parameters and the motor's timing from the site's touch
// settings and the speed its scene plays at, and the other site's skeletons mapped onto this
// site's clock.
#include <cstdint>
#include <vector>

#include "touch/remote_clock.h"
#include "touch/touch_loop.h"
#include "touch/touch_settings.h"

namespace rt {

// What the site's detector allows: the hand-mesh rule, which names the gesture; a skeleton counts as lost later than by default (the tracker
// thread shares the CPU with a CPU Vulkan driver, and a late tick is not a lost hand), later still
// where the scene plays slowly and a tracker frame stands longer; a touch holds longer without news.
TouchParameters site_touch_parameters(double time_scale);

// The motor's timing from the settings: prediction on or off, the motor's latency, and the
// predictor's time constants for hands that move `time_scale` times as fast as real ones.
MotorTiming site_motor_timing(const TouchSettings& settings, double time_scale);

class SiteTouchLoop {
 public:
  SiteTouchLoop(const TouchSettings& settings, double time_scale, TouchLoop::EventHandler on_event,
                TouchLoop::MotorHandler on_motor);

  // This site's hands, stamped with their capture time on this site's clock.
  void set_local_hands(std::vector<HandSkeleton> hands);
  // The other site's hands, in this site's frame, captured at `remote_stamp_us` on the other
  // site's clock and arrived at `arrival_us`; returns their capture time on this clock (as the
  // touch events report it).
  uint64_t set_remote_hands(std::vector<HandSkeleton> hands, uint64_t remote_stamp_us, uint64_t arrival_us);

  TouchLoop& loop() { return loop_; }
  const MotorTiming& timing() const { return timing_; }

 private:
  MotorTiming timing_;
  TouchLoop loop_;
  RemoteClock remote_clock_;
};

}  // namespace rt
