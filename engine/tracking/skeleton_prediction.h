#pragma once
// The remote hand where it is now: the receiver has the other site's skeletons only some time
// after their capture (tracker, network, rendering), so the hand it draws is where the user's
// hand was. This carries one hand forward to the moment its frame is shown: each joint's recent
// samples fitted with a velocity and an acceleration; a joint speeding up has its acceleration
// fade as the prediction reaches ahead (a hand does not keep speeding up), one slowing down stops
// rather than turning back; both are clamped to what a hand can do, and no joint is ever pushed
// behind the glass (z >= 0 in the hand's own site frame, DESIGN.md section 2).
#include <cstdint>
#include <optional>
#include <span>

#include "tracking/hand_skeleton.h"

namespace rt {

struct SkeletonPredictionParameters {
  uint64_t history_us = 100'000;           // the samples fitted: a few tracker frames
  uint64_t acceleration_fade_us = 60'000;  // the fitted acceleration decays ahead with this time constant
  double max_speed_m_s = 3.0;              // a fast clap's hand; faster is tracker noise
  double max_acceleration_m_s2 = 30.0;
  uint64_t max_lead_us = 300'000;          // never further ahead than this: a hand changes course
};

// Throws std::invalid_argument saying which parameter is wrong.
void check_skeleton_prediction_parameters(const SkeletonPredictionParameters& parameters);

// The hand of `history` (one hand's samples, oldest first, in increasing time) as it will be at
// `at_us`: the newest sample moved by each joint's fit of the samples within the history. None
// without samples. A joint that is not finite in the newest sample (a missing elbow) stays as it
// is; older samples where it is not finite are left out of its fit. The palm's orientation and
// widths are the newest sample's; timestamp_us becomes `at_us` (or the newest's, if later).
std::optional<HandSkeleton> predict_hand(std::span<const HandSkeleton> history, uint64_t at_us,
                                         const SkeletonPredictionParameters& parameters = {});

}  // namespace rt
