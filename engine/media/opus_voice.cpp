#include "media/opus_voice.h"

#include <opus.h>

#include <stdexcept>
#include <string>

namespace rt::media {

VoiceEncoder::VoiceEncoder(const VoiceEncoderOptions& options) {
  if (options.bitrate_bps < 6000 || options.bitrate_bps > 128000)
    throw std::invalid_argument("voice bitrate " + std::to_string(options.bitrate_bps) + " bit/s outside 6000..128000");
  if (options.complexity < 0 || options.complexity > 10)
    throw std::invalid_argument("voice complexity " + std::to_string(options.complexity) + " outside 0..10");
  int error = OPUS_OK;
  encoder_ = opus_encoder_create(kVoiceSampleRate, 1, OPUS_APPLICATION_VOIP, &error);
  if (error != OPUS_OK || !encoder_)
    throw std::runtime_error(std::string("cannot create the Opus encoder: ") + opus_strerror(error));
  opus_encoder_ctl(encoder_, OPUS_SET_BITRATE(options.bitrate_bps));
  opus_encoder_ctl(encoder_, OPUS_SET_COMPLEXITY(options.complexity));
  opus_encoder_ctl(encoder_, OPUS_SET_SIGNAL(OPUS_SIGNAL_VOICE));
  // Constant bitrate: the figure the link is sized for, whatever is said.
  opus_encoder_ctl(encoder_, OPUS_SET_VBR(0));
}

VoiceEncoder::~VoiceEncoder() { opus_encoder_destroy(encoder_); }

std::vector<uint8_t> VoiceEncoder::encode(std::span<const float> frame) {
  if (frame.size() != kVoiceFrameSamples)
    throw std::invalid_argument("a voice frame is " + std::to_string(kVoiceFrameSamples) + " samples, not " +
                                std::to_string(frame.size()));
  std::vector<uint8_t> packet(1275);
  const opus_int32 bytes = opus_encode_float(encoder_, frame.data(), int(frame.size()), packet.data(), opus_int32(packet.size()));
  if (bytes < 0) throw std::runtime_error(std::string("Opus encoding failed: ") + opus_strerror(bytes));
  packet.resize(size_t(bytes));
  return packet;
}

VoiceDecoder::VoiceDecoder() {
  int error = OPUS_OK;
  decoder_ = opus_decoder_create(kVoiceSampleRate, 1, &error);
  if (error != OPUS_OK || !decoder_)
    throw std::runtime_error(std::string("cannot create the Opus decoder: ") + opus_strerror(error));
}

VoiceDecoder::~VoiceDecoder() { opus_decoder_destroy(decoder_); }

std::vector<float> VoiceDecoder::decode(std::span<const uint8_t> packet) {
  std::vector<float> frame(kVoiceFrameSamples);
  const int samples = opus_decode_float(decoder_, packet.data(), opus_int32(packet.size()), frame.data(), int(frame.size()), 0);
  if (samples == int(kVoiceFrameSamples)) return frame;
  ++undecodable_;
  return conceal();
}

std::vector<float> VoiceDecoder::conceal() {
  std::vector<float> frame(kVoiceFrameSamples);
  const int samples = opus_decode_float(decoder_, nullptr, 0, frame.data(), int(frame.size()), 0);
  if (samples != int(kVoiceFrameSamples)) std::fill(frame.begin(), frame.end(), 0.0f);
  return frame;
}

}  // namespace rt::media
