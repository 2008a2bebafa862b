#pragma once
// The voice codec: Opus in VoIP mode, 48 kHz mono, one packet per 20 ms frame. The decoder
// conceals a lost frame (Opus's packet loss concealment) so that a gap sounds like a short
// smear, not a click.
#include <cstdint>
#include <span>
#include <vector>

typedef struct OpusEncoder OpusEncoder;
typedef struct OpusDecoder OpusDecoder;

namespace rt::media {

inline constexpr int kVoiceSampleRate = 48000;
inline constexpr size_t kVoiceFrameSamples = 960;  // 20 ms

struct VoiceEncoderOptions {
  int bitrate_bps = 28000;  // 24..32 kbit/s is wide-band speech at its best per bit
  int complexity = 5;       // 0..10: cost against quality; 5 is a fraction of a percent of a core
};

class VoiceEncoder {
 public:
  // Throws std::invalid_argument for a bitrate outside 6..128 kbit/s or a complexity outside 0..10.
  explicit VoiceEncoder(const VoiceEncoderOptions& options = {});
  ~VoiceEncoder();
  VoiceEncoder(const VoiceEncoder&) = delete;
  VoiceEncoder& operator=(const VoiceEncoder&) = delete;

  // One frame of exactly kVoiceFrameSamples; throws std::invalid_argument for another length.
  std::vector<uint8_t> encode(std::span<const float> frame);

 private:
  OpusEncoder* encoder_ = nullptr;
};

class VoiceDecoder {
 public:
  VoiceDecoder();
  ~VoiceDecoder();
  VoiceDecoder(const VoiceDecoder&) = delete;
  VoiceDecoder& operator=(const VoiceDecoder&) = delete;

  // One frame of kVoiceFrameSamples from `packet`; a packet Opus cannot decode is concealed like a
  // lost one (it came through the session's authentication, so it is damage, not an attack) and
  // counted.
  std::vector<float> decode(std::span<const uint8_t> packet);
  // One frame in place of a lost packet.
  std::vector<float> conceal();
  uint64_t undecodable() const { return undecodable_; }

 private:
  OpusDecoder* decoder_ = nullptr;
  uint64_t undecodable_ = 0;
};

}  // namespace rt::media
