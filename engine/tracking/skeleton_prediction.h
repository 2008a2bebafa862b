#pragma once
// The remote hand where it is now: the receiver has the other site's skeletons only some time
// after their capture (tracker, network, rendering), so the hand it draws is where the user's
// hand was. This carries one hand forward to the moment its frame is shown, as a whole: the
// centre of its joints fitted over the recent samples with a velocity and an acceleration; when
// it speeds up the acceleration fades as the prediction reaches ahead (a hand does not keep
// speeding up), when it slows down it stops rather than turning back; both are clamped to what
// a hand can do, and the hand stops at the glass (z >= 0 in its own site frame, DESIGN.md
// section 2). Its shape is the newest sample's: a turn of the hand is not carried forward.
#include <cstdint>
#include <optional>
#include <span>

#include "tracking/hand_skeleton.h"

namespace rt {

struct SkeletonPredictionParameters {
  uint64_t history_us = 160'000;           // the samples fitted: a few tracker frames
  uint64_t acceleration_fade_us = 60'000;  // the fitted acceleration decays ahead with this time constant
  double max_speed_m_s = 3.0;              // a fast clap's hand; faster is tracker noise
  // Slower than this the hand is taken as still and held: about what the tracker's noise alone
  // gives the fitted centre of a hand at rest.
  double min_speed_m_s = 0.03;
  double max_acceleration_m_s2 = 30.0;
  uint64_t max_lead_us = 300'000;          // never further ahead than this: a hand changes course
};

// Throws std::invalid_argument saying which parameter is wrong.
void check_skeleton_prediction_parameters(const SkeletonPredictionParameters& parameters);

// The hand of `history` (one hand's samples, oldest first, in increasing time) as it will be at
// `at_us`: the newest sample moved by the fit of the samples within the history. None without
// samples. A joint that is not finite in the newest sample (a missing elbow) stays as it is, and
// one that a sample lacks is left out of the centre. The palm's orientation and
// widths are the newest sample's; timestamp_us becomes `at_us` (or the newest's, if later).
std::optional<HandSkeleton> predict_hand(std::span<const HandSkeleton> history, uint64_t at_us,
                                         const SkeletonPredictionParameters& parameters = {});

}  // namespace rt
