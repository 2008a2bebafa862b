#pragma once
// The hand tracker as the rest of the system sees it: a source of frames in the device's own
// space (tracker_frame.h), to be converted into site-frame skeletons with tracker_space.h.
// Backends: simulated (tracker_sim.h, from a scene) and replay (tracker_replay.h, from a
// tracker.jsonl). The real Leap backend will live in devices/tracker/, where this interface
// should move.
#include <optional>

#include "sim/tracker_frame.h"

namespace rt::sim {

class HandTracker {
 public:
  virtual ~HandTracker() = default;
  // The next frame in time order; empty once the source has no more. Frames come as fast as
  // they are asked for: pacing them at the device's rate is the caller's business.
  virtual std::optional<TrackerFrame> next_frame() = 0;
};

}  // namespace rt::sim
