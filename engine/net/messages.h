#pragma once
// What the two sites exchange: one message type per stream. Coordinates are metres in
// the SENDER's site frame (the receiver maps them with geometry/site_frames.h); timestamps are
// microseconds of the sender's monotonic clock (engine/time/monotonic_clock.h): the two machines'
// clocks are unrelated, so a receiver restamps on arrival where it needs its own clock.
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "image/host_image.h"
#include "tracking/hand_skeleton.h"

namespace rt::net {

// Wire values: never renumber, only append (and bump kProtocolVersion if the meaning changes).
enum class MessageType : uint16_t { Eye = 1, Portrait = 2, Skeleton = 3, TouchEvent = 4, Heartbeat = 5, Signal = 6, Voice = 7 };
inline constexpr int kMessageTypeCount = 7;
const char* message_type_name(MessageType type);
// 0..kMessageTypeCount-1 for counters indexed by type.
inline int message_type_index(MessageType type) { return int(type) - 1; }
// A wire value this build speaks.
inline bool is_message_type(uint16_t type) { return type >= 1 && type <= kMessageTypeCount; }

// The remote viewer's eye: the sender renders its portrait for it.
struct EyeMessage {
  uint64_t timestamp_us = 0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // sender's site frame, metres
  bool valid = false;                             // false: the viewer's eye is not tracked now
};

// One rendered portrait for the receiver's eye: color RGBA32F straight alpha, depth R32F metres
// of camera z (0 = nothing). The target camera says which eye it was rendered for.
struct PortraitMessage {
  uint64_t frame_index = 0;
  uint64_t capture_timestamp_us = 0;
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix4d camera_from_site = Eigen::Matrix4d::Identity();
  HostImage color;  // RGBA32F, width x height; RGB goes over the wire as JPEG, alpha losslessly
  HostImage depth;  // R32F, width x height; lossless (bit-exact)
};

struct SkeletonMessage {
  uint64_t timestamp_us = 0;
  std::vector<HandSkeleton> hands;  // at most kMaxHands, sender's site frame
};

struct TouchEventMessage {
  enum class Kind : uint8_t { Start = 0, End = 1 };
  uint64_t timestamp_us = 0;
  Kind kind = Kind::Start;
  uint8_t site = 0;  // the site that detected the touch: 0 = A, 1 = B
  // Stamped by the sending session (net::Session::send): which session sent it (random, one per
  // run) and its place among that session's touch events, from 1. A touch event is sent again
  // after a reconnect until the peer acknowledges it; these let the receiver drop the copies.
  uint64_t sender_session = 0;
  uint64_t sequence = 0;
  uint8_t gesture = 0;  // rt::Gesture (touch/gesture.h): 0 palm, 1 fist, 2 finger
};

struct HeartbeatMessage {
  uint64_t timestamp_us = 0;
  uint64_t sequence = 0;
  // The newest touch event received from the peer's session `touches_acked_session`, by its
  // sequence: the peer stops sending those again.
  uint64_t touches_acked_session = 0;
  uint64_t touches_acked_sequence = 0;
  // The sender is ending its session: the close that follows is the session's end, not a loss.
  bool ending = false;
};

// WebRTC signalling over the session, where the two sites set up their WebRTC call without a
// rendezvous server: the offer, the answer, or one ICE candidate, as webrtcbin gives them.
struct SignalMessage {
  enum class Kind : uint8_t { Offer = 0, Answer = 1, Candidate = 2 };
  Kind kind = Kind::Offer;
  uint32_t mline = 0;  // a candidate's media line; 0 for a description
  std::string text;    // the SDP, or the candidate line: printable text, no NUL
};

// One frame of the near user's voice: Opus (voice/opus_voice.h), one packet per frame, numbered so
// that the receiver's jitter buffer tells a lost frame from a late one.
struct VoiceMessage {
  uint64_t timestamp_us = 0;    // capture time of the frame's first sample, sender's clock
  uint32_t sequence = 0;        // frame number, from 0, one per frame (wraps)
  uint16_t frame_samples = 0;   // at 48 kHz: 480, 960 or 1920 (10, 20 or 40 ms)
  std::vector<uint8_t> packet;  // one Opus packet, 1..kMaxVoicePacket bytes
};

using Message = std::variant<EyeMessage, PortraitMessage, SkeletonMessage, TouchEventMessage, HeartbeatMessage,
                             SignalMessage, VoiceMessage>;

MessageType message_type(const Message& message);

}  // namespace rt::net
