#pragma once
// Runs the mutual touch detector at 50 Hz in its own thread on the newest skeletons of both
// sides, and hands each event to a callback (which pulses the motor). Skeletons arrive from
// other threads (tracker, network) into newest-value slots: a stale skeleton is replaced, never
// queued.
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "touch/contact_predictor.h"
#include "touch/mutual_touch.h"

namespace rt {

// When the motor is told to pulse. Without prediction: when the detector sees the touch start,
// which is after the contact by the tracker's (and the network's) latency, and the vibration
// follows by the motor's spin-up. With it: at the predicted contact less the spin-up, so that
// the vibration starts as the palms meet; a prediction the detector does not confirm is
// cancelled, a touch seen before its predicted contact still pulses at the prediction's time,
// and a touch nobody predicted pulses when it is seen.
struct MotorTiming {
  bool predict = false;
  uint64_t motor_spin_up_us = 60'000;
  // A pulse whose touch the detector has not seen this long after the predicted contact is
  // cancelled (the tracker's and the network's latency must fit in it).
  uint64_t confirm_window_us = 150'000;
  ContactPredictionParameters prediction;
};

// Pulse: run the motor for `step` (one step of the gesture's pattern, motor_pattern in
// gesture.h: the loop times the later steps itself). Cancel: stop it (its step is empty).
enum class MotorCue { Pulse, Cancel };

struct MotorTimingCounts {
  uint64_t predicted = 0;  // pulses given ahead of a predicted contact
  uint64_t confirmed = 0;  // ... whose touch the detector then saw
  uint64_t cancelled = 0;  // ... whose touch it did not see in time
  uint64_t unpredicted = 0;  // pulses given when a touch nobody predicted was seen
};

class TouchLoop {
 public:
  using EventHandler = std::function<void(const TouchEvent&)>;
  using MotorHandler = std::function<void(MotorCue, uint64_t now_us, const MotorStep& step, Gesture gesture)>;

  // `on_motor`, where given, is told when to pulse and when to cancel, as `timing` says;
  // without it the caller pulses on the start events itself.
  TouchLoop(const TouchParameters& parameters, EventHandler on_event,
            std::chrono::microseconds period = std::chrono::microseconds(20'000), const MotorTiming& timing = {},
            MotorHandler on_motor = {});
  ~TouchLoop();  // stops the thread
  TouchLoop(const TouchLoop&) = delete;
  TouchLoop& operator=(const TouchLoop&) = delete;

  // Newest hands of each side, both in the local site frame and the local clock.
  void set_local_hands(std::vector<HandSkeleton> hands);
  void set_remote_hands(std::vector<HandSkeleton> hands);
  // A copy of this site's newest hands: where on the glass a touch happens.
  std::vector<HandSkeleton> local_hands();

  // One detection step at `now_us`, as the thread runs it; for tests and for callers that
  // drive their own clock.
  std::optional<TouchEvent> tick(uint64_t now_us);
  // A predicted pulse, or a pattern's later step, waiting for its time: when it is due (none:
  // nothing scheduled). The thread
  // wakes for one due before its next tick; a later one waits for the ticks.
  std::optional<uint64_t> pulse_due_us() const;
  void fire_due(uint64_t now_us);
  MotorTimingCounts motor_counts() const;

  void start();
  void stop();
  uint64_t ticks() const { return ticks_.load(); }

 private:
  void run();

  void time_motor(uint64_t now_us, const std::optional<TouchEvent>& event);
  void cue(MotorCue cue, uint64_t now_us, Gesture gesture = Gesture::Palm);
  void fire_scheduled(uint64_t now_us);
  void fire_pattern_steps(uint64_t now_us);

  MutualTouchDetector detector_;
  EventHandler on_event_;
  std::chrono::microseconds period_;
  MotorTiming timing_;
  MotorHandler on_motor_;
  // Under detector_mutex_: the predictor, a pulse scheduled before the next tick, a pulse given
  // and not yet confirmed (its predicted contact), and whether a cancelled reach is still going.
  ContactPredictor predictor_;
  std::optional<uint64_t> scheduled_pulse_us_, scheduled_contact_us_;
  std::optional<uint64_t> unconfirmed_contact_us_;
  bool scheduled_seen_ = false;  // the scheduled pulse's touch was already detected
  Gesture scheduled_gesture_ = Gesture::Palm;  // predictions are of palms meeting
  struct PendingStep {
    uint64_t due_us = 0;
    MotorStep step;
    Gesture gesture = Gesture::Palm;
  };
  std::vector<PendingStep> pattern_steps_;  // a pattern's later steps, due in order
  bool cancelled_reach_ = false;
  MotorTimingCounts counts_;
  std::mutex hands_mutex_;
  std::vector<HandSkeleton> local_hands_, remote_hands_;
  mutable std::mutex detector_mutex_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> ticks_{0};
  std::thread thread_;
};

}  // namespace rt
