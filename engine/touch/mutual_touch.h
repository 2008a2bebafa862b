#pragma once
// Mutual touch detection. The paper's rule (section 3.2): the joints of the local and of the
// remote hand within 2 cm of the screen, projected onto the screen plane, give two bounding
// boxes; an overlap above 50 cm^2 is a mutual touch. The hand-mesh rule (mesh_contact.h): the
// overlap of the two hands' skin on the glass, which also names the gesture. Hysteresis turns one
// clap into exactly one start event and one end event.
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "touch/mesh_contact.h"
#include "tracking/hand_skeleton.h"

namespace rt {

enum class TouchRule {
  JointBoxes,  // the paper's; every touch is a palm touch
  HandMeshes,  // the overlap of the hands' skin on the glass, the gesture named
};

struct TouchParameters {
  TouchRule rule = TouchRule::JointBoxes;
  double joint_distance_m = 0.02;  // a joint this close to the screen (inclusive) is at the glass
  double start_area_m2 = 50e-4;    // paper: an overlap above 50 cm^2 starts a touch
  // Hysteresis: a touch ends once the overlap has stayed below end_area for end_after_ticks
  // ticks (60 ms at 50 Hz), so tracker jitter around the threshold gives no second clap.
  double end_area_m2 = 25e-4;
  int end_after_ticks = 3;
  // A skeleton older than this counts as lost tracking (the tracker runs at 50 Hz) ...
  uint64_t max_skeleton_age_us = 100'000;
  // ... except during a touch: then a side's last skeleton stands until it is this old. Skeletons
  // that stop arriving for a moment (a stalled thread, a burst of network delay) say nothing
  // about the hands parting, and ending there gave one clap two starts.
  uint64_t touch_hold_age_us = 500'000;
  // A side whose hands vanish during a touch (the tracker lost them for a few frames: a dropout)
  // keeps its last hands until they are this old: a dropout says nothing about the hands parting,
  // and ending there started a second touch. Hands that are tracked leaving still end it.
  uint64_t dropout_hold_us = 250'000;
  MeshContactParameters mesh;  // the hand-mesh rule's band and grid
};

// The hand-mesh rule with its areas: two fingertips' pads overlap by about two square
// centimetres, so the paper's 50 cm^2 would miss them; a touch starts above 1 cm^2 and ends
// under a quarter of that. The skin has no box's empty corners to fake an overlap.
TouchParameters hand_mesh_touch_parameters();

// Throws with the reason unless the thresholds make sense (positive, end <= start, ...).
void check_touch_parameters(const TouchParameters& parameters);

// Bounding box, on the screen plane (x, y in metres), of the finite joints within
// joint_distance_m of the screen; empty when there are none.
std::optional<Eigen::AlignedBox2d> contact_box(const HandSkeleton& hand, double joint_distance_m);

// Largest overlap (m^2) between a local hand's contact box and a remote hand's; hands are in
// the local site frame (map the remote ones with map_skeleton first).
double overlap_area_m2(std::span<const HandSkeleton> local_hands, std::span<const HandSkeleton> remote_hands,
                       double joint_distance_m);

// The overlap by the parameters' rule and its gesture (always palm under the joint boxes);
// `cache`, where given, keeps the hand-mesh rule's patches for the next call.
MeshContact touch_overlap(std::span<const HandSkeleton> local_hands, std::span<const HandSkeleton> remote_hands,
                          const TouchParameters& parameters, ContactPatchCache* cache = nullptr);

struct TouchEvent {
  enum class Kind { Start, End };
  Kind kind = Kind::Start;
  uint64_t timestamp_us = 0;         // when the detector decided (monotonic clock)
  uint64_t local_capture_us = 0;     // capture time of the newest local skeleton used (0 if none)
  uint64_t remote_capture_us = 0;    // same for the remote side
  double overlap_area_m2 = 0.0;      // at that tick
  Gesture gesture = Gesture::Palm;   // a start's gesture; an end repeats its start's
};

const char* touch_event_name(TouchEvent::Kind kind);

class MutualTouchDetector {
 public:
  explicit MutualTouchDetector(const TouchParameters& parameters = {});

  // One tick with the newest skeletons of both sides (remote already in the local frame, its
  // timestamps already in the local clock: two machines' monotonic clocks are unrelated); an
  // empty span means that side tracks no hand. Returns the event this tick causes, if any.
  std::optional<TouchEvent> update(uint64_t now_us, std::span<const HandSkeleton> local_hands,
                                   std::span<const HandSkeleton> remote_hands);
  bool touching() const { return touching_; }
  const TouchParameters& parameters() const { return parameters_; }

 private:
  TouchParameters parameters_;
  bool touching_ = false;
  Gesture gesture_ = Gesture::Palm;
  int ticks_below_end_ = 0;
  ContactPatchCache patch_cache_;  // a tracker frame stands for several ticks: skinned once
  std::vector<HandSkeleton> last_local_, last_remote_;  // each side's last hands seen
};

}  // namespace rt
