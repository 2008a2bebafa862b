#include "media/voice_rtp_time.h"

namespace rt::media {
namespace {

uint64_t ticks_of_us(uint64_t us) { return us / 1000 * kVoiceRtpClockRate / 1000 + us % 1000 * kVoiceRtpClockRate / 1000000; }

}  // namespace

uint32_t voice_rtp_time(uint64_t capture_us) { return uint32_t(ticks_of_us(capture_us)); }

uint64_t voice_capture_us(uint32_t rtp_time, uint64_t reference_us) {
  const uint64_t reference = ticks_of_us(reference_us);
  const int64_t ticks = int64_t(reference) + int64_t(int32_t(rtp_time - uint32_t(reference)));
  if (ticks <= 0) return 0;
  // To the nearest microsecond of the tick's start (a tick is 20.8 µs).
  return (uint64_t(ticks) * 1000000 + kVoiceRtpClockRate / 2) / kVoiceRtpClockRate;
}

uint32_t SequenceExtender::extend(uint16_t sequence) {
  if (!last_) {
    last_ = sequence;
    return sequence;
  }
  const uint32_t extended = *last_ + uint32_t(int32_t(int16_t(uint16_t(sequence - uint16_t(*last_)))));
  // Only forward moves advance the run, so that a late packet does not pull it back.
  if (int32_t(extended - *last_) > 0) last_ = extended;
  return extended;
}

}  // namespace rt::media
