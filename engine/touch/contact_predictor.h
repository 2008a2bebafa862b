#pragma once
// When will the palms meet on the glass? The motor needs its command before the contact by its
// own spin-up, and the detector sees the contact only once the tracker (and, for the remote
// hand, the network) has delivered it: both come after the fact. From each side's recent
// skeletons this fits the palm's distance to the glass with a velocity and a deceleration, and
// its slide along the glass with a velocity, and predicts when both palms reach the glass, and
// whether their hands then overlap as the detector (mutual_touch.h) requires. It models palms:
// under the hand-mesh rule it predicts only for hands held flat to the glass, and a fist bump or
// a fingertip touch pulses its own pattern when the detector sees it.
#include <cstdint>
#include <deque>
#include <optional>

#include "touch/mutual_touch.h"

namespace rt {

struct ContactPredictionParameters {
  uint64_t history_us = 100'000;     // the samples fitted: the last tenth of a second of a reach
  uint64_t max_horizon_us = 250'000;  // no contact predicted further ahead: a reach changes course
  double min_approach_speed_m_s = 0.1;  // a hand slower than this hovers; it is not reaching
  double max_deceleration_m_s2 = 40.0;  // beyond this the fit follows tracker noise, not a hand
  // A side not heard from this long (a stalled link) says nothing about where its hand is now:
  // extrapolating its old reach predicted contacts far too early.
  uint64_t max_sample_age_us = 150'000;
  // The newest samples weigh most (e^(age / this)): the reach's speed and deceleration change as
  // it goes, and the contact follows from how it moves now.
  uint64_t weight_time_constant_us = 30'000;
  // The height of the hand's joints over the glass at which the palms count as met: a tracker's
  // skeleton runs through the middle of the hand, so a palm flat on the glass has its joints
  // a little way out from it (sim/motion.h); zero treats the joints as the skin.
  double contact_height_m = 0.0;
};

// The same parameters for hands that move `time_scale` times as fast as real ones on the clock
// their samples carry (below one: a site playing its scene slower than real time).
ContactPredictionParameters scaled_to_time(const ContactPredictionParameters& parameters, double time_scale);

// Throws with the reason unless the parameters make sense.
void check_contact_prediction_parameters(const ContactPredictionParameters& parameters);

class ContactPredictor {
 public:
  explicit ContactPredictor(const ContactPredictionParameters& parameters = {}, const TouchParameters& touch = {});

  // Each side's newest hands as the touch loop has them (the remote side in the local frame and
  // clock). The hand nearest the glass (on either side) is followed; a sample not newer than the last is ignored,
  // and a side without a hand forgets its history.
  void add_local(const std::vector<HandSkeleton>& hands);
  void add_remote(const std::vector<HandSkeleton>& hands);

  // When both palms will be on the glass with their hands overlapping (local clock), if they
  // are reaching for it now; none otherwise. A side already at the glass counts from its
  // newest sample.
  std::optional<uint64_t> predicted_contact_us(uint64_t now_us) const;

 private:
  struct Track {
    std::deque<HandSkeleton> samples;  // oldest first, within history of the newest
  };
  struct Reach {
    uint64_t contact_us = 0;
    HandSkeleton at_glass;  // the newest skeleton moved to where the fit puts it at contact
  };
  void add(Track& track, const std::vector<HandSkeleton>& hands);
  std::optional<Reach> reach(const Track& track, uint64_t now_us) const;

  ContactPredictionParameters parameters_;
  TouchParameters touch_;
  Track local_, remote_;
  // The hands predicted at the glass stay the same between new samples: skinned once.
  mutable ContactPatchCache patch_cache_;
};

}  // namespace rt
