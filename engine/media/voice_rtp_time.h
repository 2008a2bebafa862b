#pragma once
// The voice's RTP numbers and what they stand for. The sender stamps each Opus packet with its
// capture time as RTP time (48 kHz ticks of the sending site's monotonic clock, modulo 2^32, which
// wraps every 24.8 hours); the receiver takes the missing high bits from a recent reading of the
// same clock (the other site's heartbeat), so the capture time comes back whole without a record
// of its own beside the packet. RTP sequence numbers are 16 bits; the jitter buffer counts frames
// with 32.
#include <cstdint>
#include <optional>

namespace rt::media {

inline constexpr uint32_t kVoiceRtpClockRate = 48000;  // Opus's RTP clock, whatever it codes at

// The RTP time of a packet captured at `capture_us` (the sender's monotonic clock).
uint32_t voice_rtp_time(uint64_t capture_us);
// The capture time a packet's RTP time stands for, given `reference_us`, a reading of the sender's
// clock within 12 hours of the capture (any recent one will do). Exact to a tick (20.8 µs).
uint64_t voice_capture_us(uint32_t rtp_time, uint64_t reference_us);

// A packet's 16-bit sequence number as one of a run that does not wrap: each next to the last one
// seen, forward or back by less than half the range.
class SequenceExtender {
 public:
  uint32_t extend(uint16_t sequence);

 private:
  std::optional<uint32_t> last_;
};

}  // namespace rt::media
