#pragma once
// The sound of a touch through the glass: synthesised once at start-up (no asset to ship or
// lose), placed between the site's two loudspeakers where the palms meet as the seated user hears
// it, and mixed into the loudspeakers' stream at a given sample, so that the sound starts when the
// vibration does rather than when the sound thread next wakes.
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace rt::media {

inline constexpr int kTouchSoundRate = 48000;

enum class TouchSound { Clap, FistBump, FingerTap };
const char* touch_sound_name(TouchSound sound);

// Mono, 48 kHz, in [-1, 1], starting at its first sample: a clap is a few milliseconds of
// band-limited noise bursts (the air pushed out between two palms) over a short ring; a fist bump
// a low, dull knock; a finger tap a short, light tick. Deterministic.
std::vector<float> synthesize_touch_sound(TouchSound sound);

// Where a sound sits between the left and right loudspeakers: a level difference by constant-power
// panning and a time difference for the far ear, both from the source's azimuth as the listener's
// head sees it (Woodworth's spherical head for the time).
struct StereoPlacement {
  float gain_left = float(0.70710678);
  float gain_right = float(0.70710678);
  size_t delay_left_samples = 0;
  size_t delay_right_samples = 0;
  double azimuth_rad = 0.0;  // 0 straight ahead, positive to the listener's right
};

// `source_m` and `head_m` in the site frame (DESIGN.md: +x right as the seated user sees it, +z
// from the screen towards the user). A source level with or behind the head is placed at the side
// it leans to; a non-finite position gives the centre.
StereoPlacement place_between_loudspeakers(const Eigen::Vector3d& source_m, const Eigen::Vector3d& head_m);

// Touch sounds waiting for or being played, mixed into interleaved stereo blocks (left, right)
// of the loudspeakers' stream, whose samples are numbered from the stream's start.
class TouchSoundMixer {
 public:
  static constexpr size_t kMaxSounds = 8;  // beyond this the oldest is dropped: a stuck detector cannot pile up sound

  TouchSoundMixer();  // synthesises every kind once

  // Plays `sound` from stream sample `onset_sample` on; returns an id for cancel().
  uint64_t schedule(TouchSound sound, uint64_t onset_sample, const StereoPlacement& placement);
  // Withdraws a sound that has not started by `next_sample` (the first sample not yet mixed);
  // false once it has begun (a started sound plays out) or when the id is unknown.
  bool cancel(uint64_t id, uint64_t next_sample);
  // Adds the sounds due within `stereo` (frames from `first_sample`) and limits the sum to [-1, 1].
  void mix_into(std::span<float> stereo, uint64_t first_sample);

  size_t pending() const { return sounds_.size(); }
  uint64_t dropped() const { return dropped_; }
  const std::vector<float>& samples_of(TouchSound sound) const { return synthesized_[size_t(sound)]; }

 private:
  struct Playing {
    uint64_t id = 0;
    TouchSound sound = TouchSound::Clap;
    uint64_t onset_sample = 0;
    StereoPlacement placement;
  };
  std::array<std::vector<float>, 3> synthesized_;
  std::vector<Playing> sounds_;
  uint64_t next_id_ = 1;
  uint64_t dropped_ = 0;
};

}  // namespace rt::media
