#pragma once
// The receiver's jitter buffer for voice frames: frames arrive in bursts and out of order, the
// loudspeaker takes one every 20 ms. It holds `target_frames` before it starts playing (the
// delay that absorbs the network's jitter), plays frames in sequence, says which are lost so that
// the decoder conceals them, and is bounded: past `capacity_frames` the oldest frames go and
// playing catches up, so a stall never turns into a growing delay.
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "net/messages.h"

namespace rt::media {

struct JitterBufferOptions {
  size_t target_frames = 3;     // 60 ms at 20 ms a frame
  size_t capacity_frames = 25;  // 500 ms
  // Lost frames in a row after which the talker is taken to have stopped: play silence and
  // buffer again before playing.
  size_t rebuffer_after_lost = 10;
};

// Empty when the options work together, else what is wrong.
std::string check_jitter_buffer(const JitterBufferOptions& options);

struct JitterCounters {
  uint64_t played = 0, lost = 0, late = 0, duplicate = 0, overflow_dropped = 0, rebuffers = 0;
  // The longest run of lost frames that the voice came back after (a dropout, concealed); a run
  // that ends with the talker's frames stopping for good is no dropout.
  uint64_t longest_concealed_run = 0;
};

class VoiceJitterBuffer {
 public:
  // Throws std::invalid_argument when check_jitter_buffer says no.
  explicit VoiceJitterBuffer(const JitterBufferOptions& options = {});

  // False when the frame is not taken: already played or passed (late), or here already.
  bool push(net::VoiceMessage frame);

  enum class Slot { Silence, Frame, Lost };
  struct Playout {
    Slot slot = Slot::Silence;
    net::VoiceMessage frame;  // Slot::Frame only
  };
  // What plays in the next 20 ms.
  Playout pop();

  size_t buffered() const { return frames_.size(); }
  bool playing() const { return playing_; }
  const JitterCounters& counters() const { return counters_; }

 private:
  // Distance of `sequence` after the next one to play; negative when it is behind.
  int64_t ahead(uint32_t sequence) const { return int64_t(int32_t(sequence - next_)); }

  JitterBufferOptions options_;
  std::map<int64_t, net::VoiceMessage> frames_;  // by distance from `base_`
  uint32_t next_ = 0;
  bool have_next_ = false;
  bool playing_ = false;
  size_t lost_in_row_ = 0;
  JitterCounters counters_;
};

}  // namespace rt::media
