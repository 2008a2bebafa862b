#include "touch/touch_loop.h"

#include <algorithm>

#include "time/monotonic_clock.h"

namespace rt {

TouchLoop::TouchLoop(const TouchParameters& parameters, EventHandler on_event, std::chrono::microseconds period,
                     const MotorTiming& timing, MotorHandler on_motor)
    : detector_(parameters),
      on_event_(std::move(on_event)),
      period_(period),
      timing_(timing),
      on_motor_(std::move(on_motor)),
      predictor_(timing.prediction, parameters) {}

TouchLoop::~TouchLoop() { stop(); }

void TouchLoop::set_local_hands(std::vector<HandSkeleton> hands) {
  std::lock_guard lock(hands_mutex_);
  local_hands_ = std::move(hands);
}

std::vector<HandSkeleton> TouchLoop::local_hands() {
  std::lock_guard lock(hands_mutex_);
  return local_hands_;
}

void TouchLoop::set_remote_hands(std::vector<HandSkeleton> hands) {
  std::lock_guard lock(hands_mutex_);
  remote_hands_ = std::move(hands);
}

std::optional<TouchEvent> TouchLoop::tick(uint64_t now_us) {
  std::vector<HandSkeleton> local, remote;
  {
    std::lock_guard lock(hands_mutex_);
    local = local_hands_;
    remote = remote_hands_;
  }
  std::optional<TouchEvent> event;
  {
    std::lock_guard lock(detector_mutex_);
    event = detector_.update(now_us, local, remote);
    if (timing_.predict) {
      predictor_.add_local(local);
      predictor_.add_remote(remote);
    }
    if (on_motor_) {
      fire_pattern_steps(now_us);
      time_motor(now_us, event);
    }
  }
  ++ticks_;
  if (event && on_event_) on_event_(*event);
  return event;
}

void TouchLoop::cue(MotorCue cue, uint64_t now_us, Gesture gesture) {
  if (!on_motor_) return;
  if (cue == MotorCue::Cancel) {
    pattern_steps_.clear();
    on_motor_(cue, now_us, MotorStep{}, gesture);
    return;
  }
  const std::vector<MotorStep>& pattern = motor_pattern(gesture);
  pattern_steps_.clear();
  for (size_t i = 1; i < pattern.size(); ++i)
    pattern_steps_.push_back({now_us + uint64_t(pattern[i].after.count()) * 1000, pattern[i], gesture});
  on_motor_(cue, now_us, pattern.front(), gesture);
}

void TouchLoop::fire_pattern_steps(uint64_t now_us) {
  while (!pattern_steps_.empty() && pattern_steps_.front().due_us <= now_us) {
    const PendingStep due = pattern_steps_.front();
    pattern_steps_.erase(pattern_steps_.begin());
    on_motor_(MotorCue::Pulse, now_us, due.step, due.gesture);
  }
}

void TouchLoop::time_motor(uint64_t now_us, const std::optional<TouchEvent>& event) {
  if (event && event->kind == TouchEvent::Kind::Start) {
    scheduled_pulse_us_.reset();
    if (unconfirmed_contact_us_) {
      ++counts_.confirmed;  // the pulse is already on its way
      unconfirmed_contact_us_.reset();
      return;
    }
    // The detector's band reaches out from the glass, so a hand that slows onto it is seen
    // touching before its palm meets the glass: a pulse predicted for later waits for its time.
    if (timing_.predict)
      if (const std::optional<uint64_t> contact = predictor_.predicted_contact_us(now_us)) {
        if (*contact > now_us + timing_.motor_spin_up_us) {
          scheduled_contact_us_ = contact;
          scheduled_pulse_us_ = *contact - timing_.motor_spin_up_us;
          scheduled_seen_ = true;
          scheduled_gesture_ = event->gesture;
          return;
        }
        // Seen as the prediction comes due (within the motor's latency of the contact): the
        // pulse leaves now, as the prediction says it should, and its touch is already seen.
        ++counts_.predicted;
        ++counts_.confirmed;
        cue(MotorCue::Pulse, now_us, event->gesture);
        return;
      }
    ++counts_.unpredicted;
    cue(MotorCue::Pulse, now_us, event->gesture);
    return;
  }
  if (scheduled_seen_ && scheduled_pulse_us_) {
    // A touch that ends before its pulse's time is felt now rather than never.
    if (event && event->kind == TouchEvent::Kind::End) scheduled_pulse_us_ = now_us;
    fire_scheduled(now_us);
    return;
  }
  if (!timing_.predict || detector_.touching()) return;
  if (unconfirmed_contact_us_) {
    if (now_us > *unconfirmed_contact_us_ + timing_.confirm_window_us) {
      ++counts_.cancelled;
      unconfirmed_contact_us_.reset();
      cancelled_reach_ = true;
      cue(MotorCue::Cancel, now_us);
    }
    return;
  }
  const std::optional<uint64_t> contact = predictor_.predicted_contact_us(now_us);
  // A reach whose pulse was cancelled does not pulse again until it is over.
  if (cancelled_reach_) {
    if (!contact) cancelled_reach_ = false;
    return;
  }
  scheduled_pulse_us_.reset();
  if (!contact) return;
  const uint64_t pulse_us = *contact > timing_.motor_spin_up_us ? *contact - timing_.motor_spin_up_us : 0;
  scheduled_contact_us_ = contact;
  scheduled_gesture_ = Gesture::Palm;
  if (pulse_us <= now_us) {
    scheduled_pulse_us_ = now_us;
    fire_scheduled(now_us);
  } else if (pulse_us < now_us + uint64_t(period_.count())) {
    scheduled_pulse_us_ = pulse_us;  // between this tick and the next: the thread wakes for it
  }
}

void TouchLoop::fire_scheduled(uint64_t now_us) {
  if (!scheduled_pulse_us_ || now_us < *scheduled_pulse_us_) return;
  scheduled_pulse_us_.reset();
  ++counts_.predicted;
  if (scheduled_seen_) {
    ++counts_.confirmed;  // the detector saw the touch before the pulse's time
    scheduled_seen_ = false;
  } else {
    unconfirmed_contact_us_ = scheduled_contact_us_;
  }
  cue(MotorCue::Pulse, now_us, scheduled_gesture_);
}

std::optional<uint64_t> TouchLoop::pulse_due_us() const {
  std::lock_guard lock(detector_mutex_);
  std::optional<uint64_t> due = scheduled_pulse_us_;
  if (!pattern_steps_.empty() && (!due || pattern_steps_.front().due_us < *due)) due = pattern_steps_.front().due_us;
  return due;
}

void TouchLoop::fire_due(uint64_t now_us) {
  std::lock_guard lock(detector_mutex_);
  fire_scheduled(now_us);
  if (on_motor_) fire_pattern_steps(now_us);
}

MotorTimingCounts TouchLoop::motor_counts() const {
  std::lock_guard lock(detector_mutex_);
  return counts_;
}

void TouchLoop::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void TouchLoop::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void TouchLoop::run() {
  // sleep_until a fixed schedule, so that a slow tick does not shift every later one.
  auto next = std::chrono::steady_clock::now();
  while (running_) {
    tick(monotonic_now_us());
    next += period_;
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // fell behind (debugger, overload): skip, do not burst
    // A predicted pulse falls between ticks: wake for it, so that it is on time to the
    // microsecond rather than to the tick.
    const uint64_t next_us = monotonic_now_us() + uint64_t(std::max<int64_t>(
                                 0, std::chrono::duration_cast<std::chrono::microseconds>(next - now).count()));
    if (const std::optional<uint64_t> due = pulse_due_us(); due && *due < next_us) {
      std::this_thread::sleep_for(std::chrono::microseconds(int64_t(*due) - int64_t(monotonic_now_us())));
      fire_due(monotonic_now_us());
    }
    std::this_thread::sleep_until(next);
  }
}

}  // namespace rt

