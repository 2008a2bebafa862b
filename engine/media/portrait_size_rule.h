#pragma once
// The size a portrait is encoded at under a narrow path. The bitrate rule (media/bitrate_rule.h)
// only moves the colour rate between its floor and its ceiling; once loss holds the rate at the
// floor nothing else gives, and x264 at that rate smears the call's full-size picture (or, where
// a picture is lost, the frame rate goes). This rule gives way in size: when the rate has sat at
// (or near) its floor while the path kept losing, it steps the encoded size down (3/4, then 1/2 of
// the call's, both tracks together), and steps back up once the loss has ended. Frame rate is what
// a call feels most (a hand that stutters towards the glass); a softer picture is the lesser loss.
//
// Loss is judged by its median over a period, not by single decisions: on a loaded machine a clean
// path still draws the odd NACK for a packet that is only late (docs/webrtc.md), which reads as a
// few percent in a second of a small call. Hysteresis, so that the size does not flap: stepping
// down needs more than half the period's decisions at the floor losing more than loss_pressed,
// stepping up more than half of them at or below loss_clear (half of it), each over a whole period
// of decisions made since the last change; and a step down soon after a step up
// doubles the wait before the next step up (a path that loses whenever it is given more cycles
// otherwise every few seconds).
//
// What it does not weigh: the bits each pixel gets. It steps up on a clean path whatever the
// rate, since the size does not change the rate the path must carry (x264 holds the bitrate).
// Pure logic: the caller feeds it the bitrate rule's decisions and scales the pictures.
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace rt::media {

struct PortraitSizeRuleOptions {
  int floor_kbps = 300;          // the colour rate's floor (the bitrate rule's)
  double near_floor = 1.15;      // a rate up to this multiple of the floor is at the floor
  double loss_pressed = 0.04;    // median loss above this, every decision at the floor: step down
  double loss_clear = 0.02;      // median loss at or below this: step up
  double round_trip_high_s = 0.4;  // a decision with a longer round trip counts as all lost
  double down_after_s = 3.0;     // the period a step down weighs
  double up_after_s = 4.0;       // the period a step up weighs (before any doubling)
  // A step down this soon after a step up doubles the up period (to 8x at most); this long
  // at the call's size, it is back to up_after_s.
  double flap_window_s = 30.0;
};

// Empty when the options can be used, else what is wrong with them.
std::string check_portrait_size_rule(const PortraitSizeRuleOptions& options);

// How many steps below the call's size there are, and the size at a step: the call's size times
// 1, 3/4 or 1/2, each side rounded to an even number (the tracks are 4:2:0), at least 2.
inline constexpr int kPortraitSizeSteps = 2;
std::pair<uint32_t, uint32_t> portrait_size_at_step(uint32_t width, uint32_t height, int step);
// The receiver's side (media/portrait_pictures.h scales what it decoded back to the call's size).
// Empty when a decoded picture of this size can be scaled to the call's, else why not.
std::string check_received_picture_size(uint32_t width, uint32_t height, uint32_t call_width, uint32_t call_height);

// Depth/alpha codes (row-major, `from_width` a row) resampled to another size, each output pixel
// taking the code at the nearest input pixel centre, on both sides of the link. Nearest, not
// interpolated: interpolating across the silhouette would invent depths between the user and the
// empty code (points floating between the user and the wall) and codes in the gap that the alpha
// threshold splits arbitrarily; the nearest code is always one the sender measured, at the price
// of a blockier silhouette edge while the size is down.
std::vector<uint16_t> resample_codes_nearest(std::span<const uint16_t> codes, uint32_t from_width, uint32_t from_height,
                                             uint32_t to_width, uint32_t to_height);

class PortraitSizeRule {
 public:
  explicit PortraitSizeRule(PortraitSizeRuleOptions options);
  // One decision of the bitrate rule: when it was made (seconds on any steady clock), the colour
  // rate it set, the loss it weighed (0..1) and the round trip (s, negative when not known).
  // Returns the step the pictures should now be encoded at (0: the call's size).
  int on_decision(double now_s, int color_kbps, double fraction_lost, double round_trip_s);
  int step() const { return step_; }
  uint64_t steps_down() const { return steps_down_; }
  uint64_t steps_up() const { return steps_up_; }
  double up_after_s() const { return up_after_s_; }  // now, after any doubling

  // One decision as the rule keeps it: its loss (1 for a long round trip) and whether the rate
  // was at the floor.
  struct Decision {
    double at_s, loss;
    bool at_floor;
  };

 private:
  // The decisions of the last `period` seconds (back to the first at or before its start), or
  // empty when those since the last change do not yet cover it.
  std::deque<Decision> period_of(double now_s, double period_s) const;

  PortraitSizeRuleOptions options_;
  int step_ = 0;
  uint64_t steps_down_ = 0, steps_up_ = 0;
  double up_after_s_;
  std::deque<Decision> since_change_;
  double last_up_s_ = -1, last_change_s_ = -1;
};

}  // namespace rt::media
