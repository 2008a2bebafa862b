#include "net/message_codec.h"

#include <cmath>
#include <cstring>
#include <future>
#include <stdexcept>

#include "net/byte_io.h"
#include "net/image_codec.h"

namespace rt::net {
namespace {

constexpr uint32_t kEyePayload = 8 + 3 * 8 + 1;
// Version 2 added the palm and forearm widths (f64 each, NaN: not given) after the joints.
constexpr uint32_t kHandSize = 8 + 4 + 1 + 4 + (5 + kDigitCount * kJointsPerDigit) * 3 * 8 + 2 * 8;
constexpr uint32_t kSkeletonFixed = 8 + 1;
constexpr double kMaxHandWidth = 1.0;  // metres: wider is not a hand or a forearm
// Version 3 added the sending session and sequence to touch events, and their acknowledgement
// and the ending flag to heartbeats. Version 4 added the touch's gesture (u8) after the site.
constexpr uint32_t kTouchPayload = 8 + 1 + 1 + 1 + 8 + 8;
constexpr uint32_t kHeartbeatPayload = 8 + 8 + 8 + 8 + 1;
constexpr uint32_t kSignalFixed = 1 + 4 + 4;
constexpr uint32_t kPortraitFixed = 8 + 8 + 4 + 4 + 4 * 8 + 16 * 8;
constexpr uint32_t kVoiceFixed = 8 + 4 + 2 + 2;

// Thrown inside the decoder only, caught at its top: one place turns a failed check into a result.
struct Reject {
  DecodeErrorKind kind;
  std::string message;
};

[[noreturn]] void reject(DecodeErrorKind kind, std::string message) { throw Reject{kind, std::move(message)}; }

std::string describe(const Eigen::Vector3d& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + ")";
}

// Empty when fine, else what is wrong with `what`.
std::string check_point(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) return std::string(what) + " is not finite " + describe(v);
  if (v.cwiseAbs().maxCoeff() > kMaxCoordinate)
    return std::string(what) + " " + describe(v) + " is more than " + std::to_string(int(kMaxCoordinate)) + " m out";
  return {};
}

std::string check_hand(const HandSkeleton& hand) {
  if (!std::isfinite(hand.confidence) || hand.confidence < 0.0f || hand.confidence > 1.0f)
    return "hand confidence " + std::to_string(hand.confidence) + " is not in [0, 1]";
  for (auto [v, name] : {std::pair{&hand.wrist, "wrist"}, {&hand.palm, "palm"}, {&hand.palm_normal, "palm normal"},
                         {&hand.direction, "direction"}})
    if (auto e = check_point(*v, name); !e.empty()) return e;
  // A tracker without an elbow sends it as NaN, all three coordinates; anything else is damage.
  if (!hand.elbow.array().isNaN().all())
    if (auto e = check_point(hand.elbow, "elbow"); !e.empty()) return e + " (a missing elbow is NaN in all three)";
  for (auto [width, name] : {std::pair{hand.palm_width_m, "palm width"}, {hand.arm_width_m, "arm width"}})
    if (!std::isnan(width) && !(width > 0.0 && width <= kMaxHandWidth))
      return std::string(name) + " " + std::to_string(width) + " m is neither NaN (not given) nor in (0, " +
             std::to_string(kMaxHandWidth) + "] m";
  for (const auto& digit : hand.digits)
    for (const auto& joint : digit)
      if (auto e = check_point(joint, "digit joint"); !e.empty()) return e;
  return {};
}

std::string check_signal(const SignalMessage& m) {
  if (uint8_t(m.kind) > uint8_t(SignalMessage::Kind::Candidate))
    return "signal kind " + std::to_string(int(m.kind)) + " is not offer (0), answer (1) or candidate (2)";
  const bool candidate = m.kind == SignalMessage::Kind::Candidate;
  const uint32_t limit = candidate ? kMaxCandidateText : kMaxSignalText;
  if (m.text.empty() || m.text.size() > limit)
    return "signal text of " + std::to_string(m.text.size()) + " bytes, must be 1.." + std::to_string(limit);
  if (candidate ? m.mline >= kMaxSignalMline : m.mline != 0)
    return "signal media line " + std::to_string(m.mline) + (candidate ? " is too large" : " on a description (must be 0)");
  for (const char c : m.text)
    if (!(c == '\r' || c == '\n' || c == '\t' || (uint8_t(c) >= 0x20 && uint8_t(c) < 0x7F)))
      return "signal text holds a byte " + std::to_string(int(uint8_t(c))) + " that is not printable ASCII";
  return {};
}

std::string check_portrait_fields(const PortraitMessage& p) {
  const auto size = std::to_string(p.width) + "x" + std::to_string(p.height);
  if (p.width == 0 || p.height == 0 || p.width > kMaxPortraitSide || p.height > kMaxPortraitSide)
    return "portrait size " + size + " outside 1.." + std::to_string(kMaxPortraitSide);
  for (double f : {p.fx, p.fy})
    if (!std::isfinite(f) || f <= 0.0) return "portrait focal length " + std::to_string(f) + " is not a positive number";
  for (double c : {p.cx, p.cy})
    if (!std::isfinite(c) || std::abs(c) > 1e6) return "portrait principal point " + std::to_string(c) + " out of range";
  const Eigen::Matrix4d& m = p.camera_from_site;
  if (!m.allFinite()) return "portrait camera_from_site is not finite";
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    return "portrait camera_from_site's last row is not (0, 0, 0, 1)";
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || r.determinant() < 0.0)
    return "portrait camera_from_site is not a rigid transform";
  if (m.col(3).head<3>().cwiseAbs().maxCoeff() > kMaxCoordinate) return "portrait camera is more than 100 m out";
  return {};
}

std::string check_portrait_images(const PortraitMessage& p) {
  if (p.color.format != PixelFormat::RGBA32F || p.color.width != p.width || p.color.height != p.height)
    return "portrait color must be RGBA32F " + std::to_string(p.width) + "x" + std::to_string(p.height);
  if (p.depth.format != PixelFormat::R32F || p.depth.width != p.width || p.depth.height != p.height)
    return "portrait depth must be R32F " + std::to_string(p.width) + "x" + std::to_string(p.height);
  for (size_t i = 3; i < p.color.texels.size(); i += 4)
    if (!(p.color.texels[i] >= 0.0f && p.color.texels[i] <= 1.0f))
      return "portrait alpha " + std::to_string(p.color.texels[i]) + " at texel " + std::to_string(i / 4) + " is not in [0, 1]";
  for (size_t i = 0; i < p.depth.texels.size(); ++i)
    if (!(p.depth.texels[i] >= 0.0f && p.depth.texels[i] <= float(kMaxCoordinate)))
      return "portrait depth " + std::to_string(p.depth.texels[i]) + " at texel " + std::to_string(i) +
             " is not in [0, 100] m";
  return {};
}

std::string check_voice(uint16_t frame_samples, size_t packet_bytes) {
  if (frame_samples != 480 && frame_samples != 960 && frame_samples != 1920)
    return "voice frame of " + std::to_string(frame_samples) + " samples, must be 480, 960 or 1920 (10, 20, 40 ms at 48 kHz)";
  if (packet_bytes == 0 || packet_bytes > kMaxVoicePacket)
    return "voice packet of " + std::to_string(packet_bytes) + " bytes, must be 1.." + std::to_string(kMaxVoicePacket);
  return {};
}

void put_vector(ByteWriter& w, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) w.put<double>(v[i]);
}
Eigen::Vector3d get_vector(ByteReader& r) {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = r.get<double>();
  return v;
}

void put_blob(ByteWriter& w, const std::vector<uint8_t>& blob) {
  w.put<uint32_t>(uint32_t(blob.size()));
  w.put_bytes(blob);
}
std::span<const uint8_t> get_blob(ByteReader& r, const char* what) {
  const uint32_t length = r.get<uint32_t>();
  if (!r.ok()) reject(DecodeErrorKind::Truncated, std::string("portrait ends before the length of its ") + what);
  if (length > r.left())
    reject(DecodeErrorKind::Truncated, std::string("portrait ") + what + " declares " + std::to_string(length) +
                                           " bytes, only " + std::to_string(r.left()) + " left");
  return r.get_bytes(length);
}

void encode_payload(ByteWriter& w, const Message& message, const EncodeOptions& options) {
  auto invalid = [](const std::string& e) {
    if (!e.empty()) throw std::invalid_argument("cannot send: " + e);
  };
  std::visit(
      [&](const auto& m) {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, EyeMessage>) {
          invalid(check_point(m.eye, "eye position"));
          w.put<uint64_t>(m.timestamp_us);
          put_vector(w, m.eye);
          w.put<uint8_t>(m.valid ? 1 : 0);
        } else if constexpr (std::is_same_v<T, PortraitMessage>) {
          invalid(check_portrait_fields(m));
          invalid(check_portrait_images(m));
          w.put<uint64_t>(m.frame_index);
          w.put<uint64_t>(m.capture_timestamp_us);
          w.put<uint32_t>(m.width);
          w.put<uint32_t>(m.height);
          for (double v : {m.fx, m.fy, m.cx, m.cy}) w.put<double>(v);
          for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) w.put<double>(m.camera_from_site(row, col));
          // The three images are independent: encode them side by side.
          auto alpha = std::async(std::launch::async, [&] { return encode_float_plane_png(m.color, 3, options.png_compression); });
          auto depth = std::async(std::launch::async, [&] { return encode_float_plane_png(m.depth, 0, options.png_compression); });
          put_blob(w, encode_color_jpeg(m.color, options.jpeg_quality));
          put_blob(w, alpha.get());
          put_blob(w, depth.get());
        } else if constexpr (std::is_same_v<T, SkeletonMessage>) {
          if (m.hands.size() > kMaxHands) invalid(std::to_string(m.hands.size()) + " hands, at most 2");
          w.put<uint64_t>(m.timestamp_us);
          w.put<uint8_t>(uint8_t(m.hands.size()));
          for (const auto& hand : m.hands) {
            invalid(check_hand(hand));
            w.put<uint64_t>(hand.timestamp_us);
            w.put<int32_t>(hand.id);
            w.put<uint8_t>(hand.is_left ? 1 : 0);
            w.put<float>(hand.confidence);
            for (const auto* v : {&hand.wrist, &hand.palm, &hand.elbow, &hand.palm_normal, &hand.direction}) put_vector(w, *v);
            for (const auto& digit : hand.digits)
              for (const auto& joint : digit) put_vector(w, joint);
            w.put<double>(hand.palm_width_m);
            w.put<double>(hand.arm_width_m);
          }
        } else if constexpr (std::is_same_v<T, TouchEventMessage>) {
          if (m.site > 1) invalid("touch site " + std::to_string(m.site) + " is neither A (0) nor B (1)");
          w.put<uint64_t>(m.timestamp_us);
          w.put<uint8_t>(uint8_t(m.kind));
          w.put<uint8_t>(m.site);
          if (m.gesture > 2) invalid("touch gesture " + std::to_string(m.gesture) + " is none of palm (0), fist (1), finger (2)");
          w.put<uint8_t>(m.gesture);
          w.put<uint64_t>(m.sender_session);
          w.put<uint64_t>(m.sequence);
        } else if constexpr (std::is_same_v<T, SignalMessage>) {
          invalid(check_signal(m));
          w.put<uint8_t>(uint8_t(m.kind));
          w.put<uint32_t>(m.mline);
          w.put<uint32_t>(uint32_t(m.text.size()));
          w.put_bytes(std::span(reinterpret_cast<const uint8_t*>(m.text.data()), m.text.size()));
        } else if constexpr (std::is_same_v<T, VoiceMessage>) {
          invalid(check_voice(m.frame_samples, m.packet.size()));
          w.put<uint64_t>(m.timestamp_us);
          w.put<uint32_t>(m.sequence);
          w.put<uint16_t>(m.frame_samples);
          w.put<uint16_t>(uint16_t(m.packet.size()));
          w.put_bytes(m.packet);
        } else {
          static_assert(std::is_same_v<T, HeartbeatMessage>);
          w.put<uint64_t>(m.timestamp_us);
          w.put<uint64_t>(m.sequence);
          w.put<uint64_t>(m.touches_acked_session);
          w.put<uint64_t>(m.touches_acked_sequence);
          w.put<uint8_t>(m.ending ? 1 : 0);
        }
      },
      message);
}

uint8_t get_flag(ByteReader& r, const char* what) {
  const uint8_t v = r.get<uint8_t>();
  if (v > 1) reject(DecodeErrorKind::BadValue, std::string(what) + " is " + std::to_string(v) + ", expected 0 or 1");
  return v;
}

Message decode_payload(MessageType type, ByteReader& r, const DecodeOptions& options) {
  switch (type) {
    case MessageType::Eye: {
      EyeMessage m;
      m.timestamp_us = r.get<uint64_t>();
      m.eye = get_vector(r);
      m.valid = get_flag(r, "eye valid flag");
      if (auto e = check_point(m.eye, "eye position"); !e.empty()) reject(DecodeErrorKind::BadValue, e);
      return m;
    }
    case MessageType::Heartbeat: {
      HeartbeatMessage m;
      m.timestamp_us = r.get<uint64_t>();
      m.sequence = r.get<uint64_t>();
      m.touches_acked_session = r.get<uint64_t>();
      m.touches_acked_sequence = r.get<uint64_t>();
      m.ending = get_flag(r, "heartbeat ending flag");
      return m;
    }
    case MessageType::Signal: {
      SignalMessage m;
      const uint8_t kind = r.get<uint8_t>();
      m.mline = r.get<uint32_t>();
      const uint32_t length = r.get<uint32_t>();
      if (!r.ok()) reject(DecodeErrorKind::Truncated, "signal shorter than its fixed fields");
      if (length != r.left())
        reject(DecodeErrorKind::BadLength, "signal text declares " + std::to_string(length) + " bytes, " +
                                               std::to_string(r.left()) + " follow");
      if (kind > uint8_t(SignalMessage::Kind::Candidate))
        reject(DecodeErrorKind::BadValue, "signal kind " + std::to_string(kind) + " is not offer (0), answer (1) or candidate (2)");
      m.kind = SignalMessage::Kind(kind);
      const auto text = r.get_bytes(length);
      m.text.assign(reinterpret_cast<const char*>(text.data()), text.size());
      if (auto e = check_signal(m); !e.empty()) reject(DecodeErrorKind::BadValue, e);
      return m;
    }
    case MessageType::Voice: {
      VoiceMessage m;
      m.timestamp_us = r.get<uint64_t>();
      m.sequence = r.get<uint32_t>();
      m.frame_samples = r.get<uint16_t>();
      const uint16_t length = r.get<uint16_t>();
      if (!r.ok()) reject(DecodeErrorKind::Truncated, "shorter than its fixed fields");
      if (auto e = check_voice(m.frame_samples, length); !e.empty()) reject(DecodeErrorKind::BadValue, e);
      if (r.left() != length)
        reject(DecodeErrorKind::BadLength, "packet declares " + std::to_string(length) + " bytes, " +
                                               std::to_string(r.left()) + " follow");
      const auto bytes = r.get_bytes(length);
      m.packet.assign(bytes.begin(), bytes.end());
      return m;
    }
    case MessageType::TouchEvent: {
      TouchEventMessage m;
      m.timestamp_us = r.get<uint64_t>();
      m.kind = TouchEventMessage::Kind(get_flag(r, "touch kind"));
      m.site = get_flag(r, "touch site");
      m.gesture = r.get<uint8_t>();
      if (m.gesture > 2) reject(DecodeErrorKind::BadValue, "touch gesture " + std::to_string(m.gesture) + " is none of 0, 1, 2");
      m.sender_session = r.get<uint64_t>();
      m.sequence = r.get<uint64_t>();
      return m;
    }
    case MessageType::Skeleton: {
      SkeletonMessage m;
      m.timestamp_us = r.get<uint64_t>();
      const uint8_t count = r.get<uint8_t>();
      if (count > kMaxHands) reject(DecodeErrorKind::BadValue, std::to_string(count) + " hands, at most 2");
      if (r.left() != size_t(count) * kHandSize)
        reject(DecodeErrorKind::BadLength, "skeleton with " + std::to_string(count) + " hands needs " +
                                               std::to_string(count * kHandSize) + " more bytes, has " +
                                               std::to_string(r.left()));
      for (int i = 0; i < count; ++i) {
        HandSkeleton hand;
        hand.timestamp_us = r.get<uint64_t>();
        hand.id = r.get<int32_t>();
        hand.is_left = get_flag(r, "hand is_left");
        hand.confidence = r.get<float>();
        for (auto* v : {&hand.wrist, &hand.palm, &hand.elbow, &hand.palm_normal, &hand.direction}) *v = get_vector(r);
        for (auto& digit : hand.digits)
          for (auto& joint : digit) joint = get_vector(r);
        hand.palm_width_m = r.get<double>();
        hand.arm_width_m = r.get<double>();
        if (auto e = check_hand(hand); !e.empty()) reject(DecodeErrorKind::BadValue, "hand " + std::to_string(i) + ": " + e);
        m.hands.push_back(hand);
      }
      return m;
    }
    case MessageType::Portrait: {
      PortraitMessage m;
      m.frame_index = r.get<uint64_t>();
      m.capture_timestamp_us = r.get<uint64_t>();
      m.width = r.get<uint32_t>();
      m.height = r.get<uint32_t>();
      for (double* v : {&m.fx, &m.fy, &m.cx, &m.cy}) *v = r.get<double>();
      for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) m.camera_from_site(row, col) = r.get<double>();
      if (!r.ok()) reject(DecodeErrorKind::Truncated, "portrait shorter than its fixed fields");
      if (auto e = check_portrait_fields(m); !e.empty()) reject(DecodeErrorKind::BadValue, e);
      if (options.portrait_width && (m.width != options.portrait_width || m.height != options.portrait_height))
        reject(DecodeErrorKind::BadValue, "portrait is " + std::to_string(m.width) + "x" + std::to_string(m.height) +
                                              ", this site displays " + std::to_string(options.portrait_width) + "x" +
                                              std::to_string(options.portrait_height) + " (not decoded)");
      const auto jpeg = get_blob(r, "color JPEG");
      const auto alpha = get_blob(r, "alpha PNG");
      const auto depth = get_blob(r, "depth PNG");
      if (r.left() != 0)
        reject(DecodeErrorKind::TrailingBytes, std::to_string(r.left()) + " bytes after the portrait's depth PNG");
      // Every image's own header against the declared size before anything big is allocated.
      std::string error;
      const auto jpeg_dims = jpeg_size(jpeg, &error);
      if (!jpeg_dims) reject(DecodeErrorKind::BadImage, "color: " + error);
      if (jpeg_dims->width != m.width || jpeg_dims->height != m.height)
        reject(DecodeErrorKind::BadImage, "color JPEG is " + std::to_string(jpeg_dims->width) + "x" +
                                              std::to_string(jpeg_dims->height) + ", declared " +
                                              std::to_string(m.width) + "x" + std::to_string(m.height));
      for (auto [png, name] : {std::pair{alpha, "alpha"}, {depth, "depth"}}) {
        const auto dims = png_size(png, &error);
        if (!dims) reject(DecodeErrorKind::BadImage, std::string(name) + ": " + error);
        if (dims->width != m.width || uint64_t(dims->height) != 4ull * m.height)
          reject(DecodeErrorKind::BadImage, std::string(name) + " PNG is " + std::to_string(dims->width) + "x" +
                                                std::to_string(dims->height) + ", declared " + std::to_string(m.width) +
                                                "x" + std::to_string(m.height) + " (x4 byte planes)");
      }
      m.depth = HostImage(m.width, m.height, PixelFormat::R32F);
      m.color = HostImage(m.width, m.height, PixelFormat::RGBA32F);
      // Side by side: depth, alpha (channel 3) and color (channels 0..2) write disjoint floats.
      auto depth_error = std::async(std::launch::async, [&] { return decode_float_plane_png(depth, m.depth, 0); });
      auto alpha_error = std::async(std::launch::async, [&] { return decode_float_plane_png(alpha, m.color, 3); });
      const auto color_error = decode_color_jpeg(jpeg, m.color);
      const auto depth_result = depth_error.get();
      const auto alpha_result = alpha_error.get();
      if (depth_result) reject(DecodeErrorKind::BadImage, "depth: " + *depth_result);
      if (alpha_result) reject(DecodeErrorKind::BadImage, "alpha: " + *alpha_result);
      if (auto e = check_portrait_images(m); !e.empty()) reject(DecodeErrorKind::BadValue, e);
      if (color_error) reject(DecodeErrorKind::BadImage, "color: " + *color_error);
      return m;
    }
  }
  reject(DecodeErrorKind::UnknownType, "unknown message type");
}

bool known_type(uint16_t type) { return is_message_type(type); }

}  // namespace

const char* message_type_name(MessageType type) {
  switch (type) {
    case MessageType::Eye: return "eye";
    case MessageType::Portrait: return "portrait";
    case MessageType::Skeleton: return "skeleton";
    case MessageType::TouchEvent: return "touch";
    case MessageType::Heartbeat: return "heartbeat";
    case MessageType::Signal: return "signal";
    case MessageType::Voice: return "voice";
  }
  return "unknown";
}

MessageType message_type(const Message& message) {
  // By the alternative's type, not its place in the variant: a new alternative may go anywhere.
  return std::visit(
      [](const auto& m) {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, EyeMessage>) return MessageType::Eye;
        if constexpr (std::is_same_v<T, PortraitMessage>) return MessageType::Portrait;
        if constexpr (std::is_same_v<T, SkeletonMessage>) return MessageType::Skeleton;
        if constexpr (std::is_same_v<T, TouchEventMessage>) return MessageType::TouchEvent;
        if constexpr (std::is_same_v<T, HeartbeatMessage>) return MessageType::Heartbeat;
        if constexpr (std::is_same_v<T, SignalMessage>) return MessageType::Signal;
        if constexpr (std::is_same_v<T, VoiceMessage>) return MessageType::Voice;
      },
      message);
}

const char* decode_error_kind_name(DecodeErrorKind kind) {
  switch (kind) {
    case DecodeErrorKind::BadMagic: return "bad_magic";
    case DecodeErrorKind::BadVersion: return "bad_version";
    case DecodeErrorKind::UnknownType: return "unknown_type";
    case DecodeErrorKind::BadLength: return "bad_length";
    case DecodeErrorKind::Truncated: return "truncated";
    case DecodeErrorKind::TrailingBytes: return "trailing_bytes";
    case DecodeErrorKind::BadValue: return "bad_value";
    case DecodeErrorKind::BadImage: return "bad_image";
  }
  return "unknown";
}

uint32_t max_payload_size(MessageType type) {
  switch (type) {
    case MessageType::Eye: return kEyePayload;
    case MessageType::Portrait: return kMaxPortraitPayload;
    case MessageType::Skeleton: return kSkeletonFixed + kMaxHands * kHandSize;
    case MessageType::TouchEvent: return kTouchPayload;
    case MessageType::Heartbeat: return kHeartbeatPayload;
    case MessageType::Signal: return kSignalFixed + kMaxSignalText;
    case MessageType::Voice: return kVoiceFixed + uint32_t(kMaxVoicePacket);
  }
  return 0;
}

std::vector<uint8_t> encode_message(const Message& message, const EncodeOptions& options) {
  std::vector<uint8_t> out;
  ByteWriter w(out);
  w.put_bytes(kMagic);
  w.put<uint16_t>(kProtocolVersion);
  w.put<uint16_t>(uint16_t(message_type(message)));
  w.put<uint32_t>(0);  // payload length, patched below
  encode_payload(w, message, options);
  const size_t payload = out.size() - kHeaderSize;
  if (payload > max_payload_size(message_type(message)))
    throw std::invalid_argument("cannot send: " + std::string(message_type_name(message_type(message))) + " of " +
                                std::to_string(payload) + " bytes is over the limit");
  const uint32_t length = uint32_t(payload);
  std::memcpy(out.data() + 8, &length, 4);
  return out;
}

std::optional<MessageHeader> decode_header(std::span<const uint8_t> bytes, DecodeError* error) {
  auto fail = [&](DecodeErrorKind kind, std::string message) -> std::optional<MessageHeader> {
    *error = {kind, std::move(message)};
    return std::nullopt;
  };
  if (bytes.size() < kHeaderSize)
    return fail(DecodeErrorKind::Truncated,
                "message of " + std::to_string(bytes.size()) + " bytes is shorter than the 12-byte header");
  if (std::memcmp(bytes.data(), kMagic, 4) != 0) return fail(DecodeErrorKind::BadMagic, "bad magic (not \"RTNM\")");
  ByteReader r(bytes.subspan(4));
  MessageHeader h;
  h.version = r.get<uint16_t>();
  h.type = r.get<uint16_t>();
  h.payload_length = r.get<uint32_t>();
  if (h.version != kProtocolVersion)
    return fail(DecodeErrorKind::BadVersion, "protocol version " + std::to_string(h.version) + ", this build speaks " +
                                                 std::to_string(kProtocolVersion));
  if (!known_type(h.type))
    return fail(DecodeErrorKind::UnknownType, "unknown message type " + std::to_string(h.type));
  const auto type = MessageType(h.type);
  const uint32_t limit = max_payload_size(type);
  const bool fixed = type == MessageType::Eye || type == MessageType::TouchEvent || type == MessageType::Heartbeat;
  if (fixed ? h.payload_length != limit : h.payload_length > limit)
    return fail(DecodeErrorKind::BadLength, std::string(message_type_name(type)) + " payload of " +
                                                std::to_string(h.payload_length) + " bytes, " +
                                                (fixed ? "must be " : "limit ") + std::to_string(limit));
  return h;
}

DecodeResult decode_message(std::span<const uint8_t> bytes, const DecodeOptions& options) {
  DecodeResult result;
  const auto header = decode_header(bytes, &result.error);
  if (!header) return result;
  const size_t available = bytes.size() - kHeaderSize;
  const auto type = MessageType(header->type);
  const std::string name = message_type_name(type);
  if (available < header->payload_length) {
    result.error = {DecodeErrorKind::Truncated, name + " truncated: payload of " + std::to_string(header->payload_length) +
                                                    " bytes declared, " + std::to_string(available) + " present"};
    return result;
  }
  if (available > header->payload_length) {
    result.error = {DecodeErrorKind::TrailingBytes, std::to_string(available - header->payload_length) +
                                                        " trailing bytes after the " + name + " payload"};
    return result;
  }
  try {
    ByteReader r(bytes.subspan(kHeaderSize));
    Message message = decode_payload(type, r, options);
    if (!r.ok()) reject(DecodeErrorKind::Truncated, name + " payload ends inside a field");
    if (r.left() != 0) reject(DecodeErrorKind::TrailingBytes, std::to_string(r.left()) + " unread bytes in the " + name + " payload");
    result.message = std::move(message);
  } catch (const Reject& e) {
    result.error = {e.kind, name + ": " + e.message};
  } catch (const std::bad_alloc&) {
    result.error = {DecodeErrorKind::BadImage, name + ": out of memory while decoding"};
  }
  return result;
}

}  // namespace rt::net
