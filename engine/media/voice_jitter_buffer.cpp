#include "media/voice_jitter_buffer.h"

#include <algorithm>
#include <stdexcept>

namespace rt::media {

std::string check_jitter_buffer(const JitterBufferOptions& o) {
  if (o.target_frames < 1 || o.target_frames > 50) return "jitter buffer target " + std::to_string(o.target_frames) + " frames outside 1..50";
  if (o.capacity_frames < o.target_frames || o.capacity_frames > 500)
    return "jitter buffer capacity " + std::to_string(o.capacity_frames) + " frames must be target.." + "500";
  if (o.rebuffer_after_lost < 1) return "jitter buffer rebuffer_after_lost must be at least 1";
  return {};
}

VoiceJitterBuffer::VoiceJitterBuffer(const JitterBufferOptions& options) : options_(options) {
  if (auto error = check_jitter_buffer(options); !error.empty()) throw std::invalid_argument(error);
}

bool VoiceJitterBuffer::push(net::VoiceMessage frame) {
  if (!have_next_) {
    next_ = frame.sequence;
    have_next_ = true;
  }
  // Before playing starts, an earlier frame than the first one seen moves the start back.
  if (!playing_ && ahead(frame.sequence) < 0 && ahead(frame.sequence) > -int64_t(options_.capacity_frames)) {
    std::map<int64_t, net::VoiceMessage> shifted;
    const int64_t shift = -ahead(frame.sequence);
    for (auto& [at, f] : frames_) shifted.emplace(at + shift, std::move(f));
    frames_ = std::move(shifted);
    next_ = frame.sequence;
  }
  const int64_t at = ahead(frame.sequence);
  if (at < 0) {
    ++counters_.late;
    return false;
  }
  if (frames_.count(at)) {
    ++counters_.duplicate;
    return false;
  }
  frames_.emplace(at, std::move(frame));
  // Bounded: drop what is oldest and skip playing ahead to it.
  while (!frames_.empty() && frames_.rbegin()->first >= int64_t(options_.capacity_frames)) {
    const auto oldest = frames_.begin();
    if (oldest->first == 0) {
      ++counters_.overflow_dropped;
      frames_.erase(oldest);
    }
    // Moving the start on by one: every key drops by one.
    std::map<int64_t, net::VoiceMessage> shifted;
    for (auto& [k, f] : frames_)
      if (k >= 1) shifted.emplace(k - 1, std::move(f));
    frames_ = std::move(shifted);
    ++next_;
  }
  return true;
}

VoiceJitterBuffer::Playout VoiceJitterBuffer::pop() {
  Playout out;
  if (!playing_) {
    if (frames_.empty() || frames_.rbegin()->first + 1 < int64_t(options_.target_frames)) return out;
    playing_ = true;
  }
  std::map<int64_t, net::VoiceMessage> shifted;
  const auto first = frames_.find(0);
  if (first != frames_.end()) {
    out.slot = Slot::Frame;
    out.frame = std::move(first->second);
    frames_.erase(first);
    ++counters_.played;
    counters_.longest_concealed_run = std::max<uint64_t>(counters_.longest_concealed_run, lost_in_row_);
    lost_in_row_ = 0;
  } else {
    out.slot = Slot::Lost;
    ++counters_.lost;
    ++lost_in_row_;
  }
  for (auto& [k, f] : frames_) shifted.emplace(k - 1, std::move(f));
  frames_ = std::move(shifted);
  ++next_;
  if (lost_in_row_ >= options_.rebuffer_after_lost && frames_.empty()) {
    // The talker's frames stopped: wait for enough of the next ones before playing again.
    playing_ = false;
    have_next_ = false;
    lost_in_row_ = 0;
    ++counters_.rebuffers;
  }
  return out;
}

}  // namespace rt::media
