#pragma once
// The versioned, length-prefixed binary message format (engine/net/README.md has the byte
// layout). Pure functions, no sockets and no cryptography: the record layer (secure_channel.h)
// seals one encoded message per record, and the fuzzer links just this codec.
//
//   header (12 bytes, little-endian): magic "RTNM" | version u16 | type u16 | payload length u32
//   payload: per type, see the encoders in message_codec.cpp.
//
// The decoder takes untrusted bytes and returns either a message or an error naming what is
// wrong: magic, version, type, length (each type has a hard limit), truncation, trailing bytes,
// non-finite or out-of-range values, image sizes that disagree with the declared ones, images
// that fail to decode.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "net/messages.h"

namespace rt::net {

inline constexpr uint8_t kMagic[4] = {'R', 'T', 'N', 'M'};
// 2: skeletons carry palm and arm widths, NaN elbows; 3: touch events are acknowledged; 4: touch
// events name their gesture
inline constexpr uint16_t kProtocolVersion = 4;
inline constexpr size_t kHeaderSize = 12;
inline constexpr uint32_t kMaxPortraitPayload = 64u << 20;  // 64 MiB
inline constexpr uint32_t kMaxPortraitSide = 4096;          // pixels, either side
inline constexpr size_t kMaxHands = 2;
// Coordinates beyond this many metres from the site origin are rejected as nonsense.
inline constexpr double kMaxCoordinate = 100.0;
// A signal's text: an SDP within kMaxSignalText (webrtcbin's for the call is far smaller), a
// candidate within kMaxCandidateText; a candidate's media line below kMaxSignalMline.
inline constexpr uint32_t kMaxSignalText = 256 * 1024;
inline constexpr uint32_t kMaxCandidateText = 1024;
inline constexpr uint32_t kMaxSignalMline = 64;
// The largest Opus packet (RFC 6716: 1275 bytes for one frame).
inline constexpr size_t kMaxVoicePacket = 1275;
// The largest encoded message of any type (header included): the record layer's limit.
inline constexpr size_t kMaxMessageSize = kHeaderSize + kMaxPortraitPayload;

// Payload size limit per type (fixed-size types: exactly this size).
uint32_t max_payload_size(MessageType type);

struct EncodeOptions {
  int jpeg_quality = 90;     // 1..100, portrait color
  int png_compression = 1;   // 0..9, portrait alpha and depth (lossless at every level)
};

// Throws std::invalid_argument when the message cannot be sent as it is (image sizes or formats
// that disagree with width/height, NaN coordinates, more than two hands, ...): the receiver would
// reject it, so the sender learns it first.
std::vector<uint8_t> encode_message(const Message& message, const EncodeOptions& options = {});

enum class DecodeErrorKind { BadMagic, BadVersion, UnknownType, BadLength, Truncated, TrailingBytes, BadValue, BadImage };
const char* decode_error_kind_name(DecodeErrorKind kind);

struct DecodeError {
  DecodeErrorKind kind = DecodeErrorKind::BadValue;
  std::string message;  // what is wrong, for the log line
};

struct DecodeResult {
  std::optional<Message> message;
  DecodeError error;  // meaningful when !message
  bool ok() const { return message.has_value(); }
};

// What the receiving side accepts beyond the format's own limits.
struct DecodeOptions {
  // The portrait size the receiver displays (0 x 0: any within kMaxPortraitSide): a portrait of
  // another declared size is refused before any of its images is decoded.
  uint32_t portrait_width = 0, portrait_height = 0;
};

// Exactly one message: the header, then exactly `payload length` bytes.
DecodeResult decode_message(std::span<const uint8_t> bytes, const DecodeOptions& options = {});

struct MessageHeader {
  uint16_t version = 0;
  uint16_t type = 0;
  uint32_t payload_length = 0;
};
// Reads and checks only the header (magic, version, known type, length within the type's limit).
std::optional<MessageHeader> decode_header(std::span<const uint8_t> bytes, DecodeError* error);

}  // namespace rt::net
