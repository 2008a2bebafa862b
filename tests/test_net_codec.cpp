// The message codec: round trips (depth and alpha bit-exact, color within a stated PSNR) and
// every way a message can be malformed, each rejected with the right kind and a clear reason.
#include <catch2/catch.hpp>

#include <cstring>
#include <random>

#include "net/byte_io.h"
#include "net/image_codec.h"
#include "net/message_codec.h"
#include "net_test_messages.h"

using namespace rt;
using namespace rt::net;

namespace {

template <typename T>
T round_trip(const Message& message) {
  const auto bytes = encode_message(message);
  const DecodeResult result = decode_message(bytes);
  INFO(result.error.message);
  REQUIRE(result.ok());
  REQUIRE(std::holds_alternative<T>(*result.message));
  return std::get<T>(*result.message);
}

DecodeError expect_rejected(const std::vector<uint8_t>& bytes, DecodeErrorKind kind, const std::string& mentions) {
  const DecodeResult result = decode_message(bytes);
  REQUIRE_FALSE(result.ok());
  INFO("error: " << result.error.message);
  CHECK(result.error.kind == kind);
  CHECK_THAT(result.error.message, Catch::Contains(mentions));
  return result.error;
}

void patch_u32(std::vector<uint8_t>& bytes, size_t at, uint32_t value) { std::memcpy(&bytes[at], &value, 4); }
void patch_f64(std::vector<uint8_t>& bytes, size_t at, double value) { std::memcpy(&bytes[at], &value, 8); }

// A portrait message assembled from given image blobs, as a buggy or hostile sender could.
std::vector<uint8_t> portrait_bytes(const PortraitMessage& p, const std::vector<uint8_t>& jpeg,
                                    const std::vector<uint8_t>& alpha, const std::vector<uint8_t>& depth) {
  std::vector<uint8_t> out;
  ByteWriter w(out);
  w.put_bytes(kMagic);
  w.put<uint16_t>(kProtocolVersion);
  w.put<uint16_t>(uint16_t(MessageType::Portrait));
  w.put<uint32_t>(0);
  w.put<uint64_t>(p.frame_index);
  w.put<uint64_t>(p.capture_timestamp_us);
  w.put<uint32_t>(p.width);
  w.put<uint32_t>(p.height);
  for (double v : {p.fx, p.fy, p.cx, p.cy}) w.put<double>(v);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) w.put<double>(p.camera_from_site(r, c));
  for (const auto* blob : {&jpeg, &alpha, &depth}) {
    w.put<uint32_t>(uint32_t(blob->size()));
    w.put_bytes(*blob);
  }
  patch_u32(out, 8, uint32_t(out.size() - kHeaderSize));
  return out;
}

double psnr_rgb(const HostImage& a, const HostImage& b) {
  double sum = 0;
  size_t n = 0;
  for (uint32_t y = 0; y < a.height; ++y)
    for (uint32_t x = 0; x < a.width; ++x)
      for (uint32_t c = 0; c < 3; ++c, ++n) {
        const double d = double(a.at(x, y, c)) - double(b.at(x, y, c));
        sum += d * d;
      }
  return 10.0 * std::log10(1.0 / (sum / double(n)));
}

}  // namespace

TEST_CASE("small messages round-trip exactly") {
  const auto eye = round_trip<EyeMessage>(EyeMessage{123456789, {0.0125, -0.25, -0.7}, true});
  CHECK(eye.timestamp_us == 123456789);
  CHECK(eye.eye == Eigen::Vector3d(0.0125, -0.25, -0.7));
  CHECK(eye.valid);
  CHECK_FALSE(round_trip<EyeMessage>(EyeMessage{1, {0, 0, 0}, false}).valid);

  const auto touch = round_trip<TouchEventMessage>(TouchEventMessage{99, TouchEventMessage::Kind::End, 1, 0xABCDEF0123ull, 41, 2});
  CHECK(touch.timestamp_us == 99);
  CHECK(touch.kind == TouchEventMessage::Kind::End);
  CHECK(touch.site == 1);
  CHECK(touch.sender_session == 0xABCDEF0123ull);
  CHECK(touch.sequence == 41);
  CHECK(touch.gesture == 2);

  const auto heartbeat = round_trip<HeartbeatMessage>(HeartbeatMessage{77, 0xFFFFFFFFFFull, 0x1234567890ull, 3});
  CHECK(heartbeat.timestamp_us == 77);
  CHECK(heartbeat.sequence == 0xFFFFFFFFFFull);
  CHECK(heartbeat.touches_acked_session == 0x1234567890ull);
  CHECK(heartbeat.touches_acked_sequence == 3);

  const SkeletonMessage sent = test::test_skeleton(5'000'000);
  const auto skeleton = round_trip<SkeletonMessage>(sent);
  CHECK(skeleton.timestamp_us == sent.timestamp_us);
  REQUIRE(skeleton.hands.size() == 2);
  for (size_t h = 0; h < 2; ++h) {
    const auto &a = skeleton.hands[h], &b = sent.hands[h];
    CHECK(a.timestamp_us == b.timestamp_us);
    CHECK(a.id == b.id);
    CHECK(a.is_left == b.is_left);
    CHECK(a.confidence == b.confidence);
    CHECK(a.wrist == b.wrist);
    CHECK(a.palm == b.palm);
    CHECK(a.has_elbow() == b.has_elbow());
    if (b.has_elbow()) CHECK(a.elbow == b.elbow);
    CHECK((a.palm_width_m == b.palm_width_m || (std::isnan(a.palm_width_m) && std::isnan(b.palm_width_m))));
    CHECK((a.arm_width_m == b.arm_width_m || (std::isnan(a.arm_width_m) && std::isnan(b.arm_width_m))));
    CHECK(a.palm_normal == b.palm_normal);
    CHECK(a.direction == b.direction);
    for (int d = 0; d < kDigitCount; ++d)
      for (int j = 0; j < kJointsPerDigit; ++j) CHECK(a.digits[d][j] == b.digits[d][j]);
  }
  CHECK(round_trip<SkeletonMessage>(SkeletonMessage{3, {}}).hands.empty());
}

TEST_CASE("signals round-trip, and bad ones are refused on both sides") {
  const std::string sdp = "v=0\r\no=- 1 0 IN IP4 0.0.0.0\r\ns=-\r\nt=0 0\r\n";
  const auto offer = round_trip<SignalMessage>(SignalMessage{SignalMessage::Kind::Offer, 0, sdp});
  CHECK(offer.kind == SignalMessage::Kind::Offer);
  CHECK(offer.text == sdp);
  const auto candidate = round_trip<SignalMessage>(
      SignalMessage{SignalMessage::Kind::Candidate, 2, "candidate:1 1 UDP 2015363327 127.0.0.1 40000 typ host"});
  CHECK(candidate.mline == 2);
  CHECK(round_trip<SignalMessage>(SignalMessage{SignalMessage::Kind::Answer, 0, sdp}).kind == SignalMessage::Kind::Answer);
  // The encoder refuses what the decoder would.
  CHECK_THROWS_WITH(encode_message(SignalMessage{SignalMessage::Kind::Offer, 0, ""}), Catch::Contains("must be 1.."));
  CHECK_THROWS_WITH(encode_message(SignalMessage{SignalMessage::Kind::Offer, 0, std::string(kMaxSignalText + 1, 'a')}),
                    Catch::Contains("must be 1.."));
  CHECK_THROWS_WITH(encode_message(SignalMessage{SignalMessage::Kind::Candidate, 0, std::string(kMaxCandidateText + 1, 'a')}),
                    Catch::Contains("must be 1.."));
  CHECK_THROWS_WITH(encode_message(SignalMessage{SignalMessage::Kind::Offer, 3, sdp}), Catch::Contains("on a description"));
  CHECK_THROWS_WITH(encode_message(SignalMessage{SignalMessage::Kind::Candidate, kMaxSignalMline, "c"}),
                    Catch::Contains("too large"));
  CHECK_THROWS_WITH(encode_message(SignalMessage{SignalMessage::Kind::Offer, 0, std::string("v=0\0x", 5)}),
                    Catch::Contains("not printable"));
  // The decoder: a bad kind, a length that disagrees, bytes that are not text.
  const auto good = encode_message(SignalMessage{SignalMessage::Kind::Offer, 0, "v=0"});
  auto bad_kind = good;
  bad_kind[kHeaderSize] = 7;
  expect_rejected(bad_kind, DecodeErrorKind::BadValue, "signal kind 7");
  auto bad_length = good;
  bad_length[kHeaderSize + 5] = 9;
  expect_rejected(bad_length, DecodeErrorKind::BadLength, "declares 9 bytes");
  auto control = good;
  control.back() = 0x01;
  expect_rejected(control, DecodeErrorKind::BadValue, "not printable");
  auto truncated = std::vector<uint8_t>(good.begin(), good.begin() + kHeaderSize + 3);
  truncated[8] = 3;
  expect_rejected(truncated, DecodeErrorKind::Truncated, "fixed fields");
}

TEST_CASE("portrait: depth and alpha bit-exact, color within PSNR, camera exact") {
  for (auto [w, h] : {std::pair{37u, 23u}, {1u, 1u}, {64u, 9u}}) {
    const PortraitMessage sent = test::test_portrait(w, h, 42);
    const auto got = round_trip<PortraitMessage>(sent);
    CHECK(got.frame_index == 42);
    CHECK(got.capture_timestamp_us == sent.capture_timestamp_us);
    CHECK(got.width == w);
    CHECK(got.height == h);
    CHECK(got.fx == sent.fx);
    CHECK(got.fy == sent.fy);
    CHECK(got.cx == sent.cx);
    CHECK(got.cy == sent.cy);
    CHECK(got.camera_from_site == sent.camera_from_site);
    REQUIRE(got.depth.format == PixelFormat::R32F);
    REQUIRE(got.color.format == PixelFormat::RGBA32F);
    REQUIRE(got.depth.texels.size() == sent.depth.texels.size());
    CHECK(std::memcmp(got.depth.texels.data(), sent.depth.texels.data(), sent.depth.texels.size() * 4) == 0);
    for (size_t i = 3; i < sent.color.texels.size(); i += 4)
      REQUIRE(std::bit_cast<uint32_t>(got.color.texels[i]) == std::bit_cast<uint32_t>(sent.color.texels[i]));
    if (w * h > 100) {
      // JPEG quality 90 on a smooth portrait-like image: stated bound 32 dB.
      const double psnr = psnr_rgb(got.color, sent.color);
      INFO("PSNR " << psnr << " dB");
      CHECK(psnr > 32.0);
    }
  }
}

TEST_CASE("JPEG quality is a parameter: lower quality, fewer bytes") {
  const PortraitMessage p = test::test_portrait(96, 64, 1);
  const size_t high = encode_message(p, {.jpeg_quality = 95}).size();
  const size_t low = encode_message(p, {.jpeg_quality = 20}).size();
  CHECK(low < high);
}

TEST_CASE("the encoder refuses what the decoder would reject") {
  CHECK_THROWS_WITH(encode_message(EyeMessage{1, {std::nan(""), 0, 0}, true}), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(encode_message(EyeMessage{1, {0, 0, 1000}, true}), Catch::Contains("100 m"));
  SkeletonMessage three = test::test_skeleton(1);
  three.hands.push_back(three.hands[0]);
  CHECK_THROWS_WITH(encode_message(three), Catch::Contains("at most 2"));
  PortraitMessage p = test::test_portrait(8, 8, 1);
  p.width = 9;
  CHECK_THROWS_WITH(encode_message(p), Catch::Contains("must be RGBA32F 9x8"));
  p = test::test_portrait(8, 8, 1);
  p.depth.at(3, 3) = -1.0f;
  CHECK_THROWS_WITH(encode_message(p), Catch::Contains("depth -1"));
  CHECK_THROWS_WITH(encode_message(TouchEventMessage{1, TouchEventMessage::Kind::Start, 2}), Catch::Contains("site"));
  CHECK_THROWS_WITH(encode_message(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0, 0, 0, 3}), Catch::Contains("gesture"));
}

TEST_CASE("malformed headers are rejected with what is wrong") {
  const auto good = encode_message(HeartbeatMessage{1, 2});
  auto bytes = good;
  bytes[0] = 'X';
  expect_rejected(bytes, DecodeErrorKind::BadMagic, "magic");
  bytes = good;
  bytes[4] = uint8_t(kProtocolVersion + 1);
  expect_rejected(bytes, DecodeErrorKind::BadVersion, "version " + std::to_string(kProtocolVersion + 1));
  bytes[4] = 1;  // a version-1 peer (skeletons without widths) is told, not misread
  expect_rejected(bytes, DecodeErrorKind::BadVersion, "version 1");
  bytes = good;
  bytes[6] = 9;
  expect_rejected(bytes, DecodeErrorKind::UnknownType, "type 9");
  bytes = good;
  bytes[6] = 0;
  expect_rejected(bytes, DecodeErrorKind::UnknownType, "type 0");
  bytes = good;
  patch_u32(bytes, 8, 17);
  expect_rejected(bytes, DecodeErrorKind::BadLength, "must be 33");
  bytes = encode_message(test::test_portrait(4, 4, 1));
  patch_u32(bytes, 8, kMaxPortraitPayload + 1);
  expect_rejected(bytes, DecodeErrorKind::BadLength, "limit 67108864");
  expect_rejected(std::vector<uint8_t>(good.begin(), good.begin() + 5), DecodeErrorKind::Truncated, "shorter than the 12-byte header");
  expect_rejected({}, DecodeErrorKind::Truncated, "0 bytes");
  expect_rejected(std::vector<uint8_t>(good.begin(), good.end() - 1), DecodeErrorKind::Truncated, "32 present");
  bytes = good;
  bytes.push_back(0);
  expect_rejected(bytes, DecodeErrorKind::TrailingBytes, "1 trailing");
}

TEST_CASE("bad values are rejected: NaN, Inf, out of range, bad flags, hand counts") {
  auto eye = encode_message(EyeMessage{1, {0.1, 0.2, 0.3}, true});
  patch_f64(eye, kHeaderSize + 8, std::nan(""));
  expect_rejected(eye, DecodeErrorKind::BadValue, "eye position is not finite");
  patch_f64(eye, kHeaderSize + 8, std::numeric_limits<double>::infinity());
  expect_rejected(eye, DecodeErrorKind::BadValue, "not finite");
  patch_f64(eye, kHeaderSize + 8, -250.0);
  expect_rejected(eye, DecodeErrorKind::BadValue, "100 m");
  eye = encode_message(EyeMessage{1, {0.1, 0.2, 0.3}, true});
  eye.back() = 2;
  expect_rejected(eye, DecodeErrorKind::BadValue, "valid flag is 2");

  auto touch = encode_message(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  touch[kHeaderSize + 9] = 7;  // after the timestamp and the kind
  expect_rejected(touch, DecodeErrorKind::BadValue, "touch site is 7");
  touch = encode_message(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  touch[kHeaderSize + 10] = 9;  // after the site
  expect_rejected(touch, DecodeErrorKind::BadValue, "touch gesture 9");

  auto skeleton = encode_message(test::test_skeleton(10));
  const size_t first_hand = kHeaderSize + 9;
  patch_f64(skeleton, first_hand + 17 + 8, std::nan(""));  // wrist.y of hand 0
  expect_rejected(skeleton, DecodeErrorKind::BadValue, "hand 0: wrist is not finite");
  skeleton = encode_message(test::test_skeleton(10));
  float confidence = 1.5f;
  std::memcpy(&skeleton[first_hand + 13], &confidence, 4);
  expect_rejected(skeleton, DecodeErrorKind::BadValue, "confidence");
  skeleton = encode_message(test::test_skeleton(10));
  skeleton[kHeaderSize + 8] = 3;  // hand count
  expect_rejected(skeleton, DecodeErrorKind::BadValue, "3 hands");
  skeleton[kHeaderSize + 8] = 1;  // one hand declared, two present
  expect_rejected(skeleton, DecodeErrorKind::BadLength, "1 hands needs");
}

TEST_CASE("skeletons: a missing elbow and missing widths travel as NaN; damaged ones are refused") {
  const SkeletonMessage sent = test::test_skeleton(10);
  REQUIRE_FALSE(sent.hands[0].has_elbow());  // the right hand's tracker gave no elbow and no widths
  REQUIRE(sent.hands[1].has_elbow());
  const auto back = round_trip<SkeletonMessage>(sent);
  CHECK_FALSE(back.hands[0].has_elbow());
  CHECK(std::isnan(back.hands[0].palm_width_m));
  CHECK(std::isnan(back.hands[0].arm_width_m));
  CHECK(back.hands[1].palm_width_m == sent.hands[1].palm_width_m);
  CHECK(back.hands[1].arm_width_m == sent.hands[1].arm_width_m);

  const size_t first_hand = kHeaderSize + 9;
  const size_t elbow = first_hand + 17 + 2 * 24, widths = first_hand + 17 + 30 * 24;
  auto skeleton = encode_message(sent);
  patch_f64(skeleton, elbow + 8, 0.25);  // one coordinate of the NaN elbow
  expect_rejected(skeleton, DecodeErrorKind::BadValue, "hand 0: elbow is not finite");
  skeleton = encode_message(sent);
  patch_f64(skeleton, widths, -0.08);
  expect_rejected(skeleton, DecodeErrorKind::BadValue, "hand 0: palm width");
  skeleton = encode_message(sent);
  patch_f64(skeleton, widths + 8, std::numeric_limits<double>::infinity());
  expect_rejected(skeleton, DecodeErrorKind::BadValue, "arm width");
  SkeletonMessage bad = sent;
  bad.hands[1].arm_width_m = 3.0;
  CHECK_THROWS_WITH(encode_message(bad), Catch::Matchers::Contains("arm width"));
}

TEST_CASE("portraits: bad fields, image sizes that disagree, corrupt images") {
  const PortraitMessage p = test::test_portrait(16, 12, 3);
  const auto jpeg = encode_color_jpeg(p.color, 90);
  const auto alpha = encode_float_plane_png(p.color, 3, 1);
  const auto depth = encode_float_plane_png(p.depth, 0, 1);
  REQUIRE(decode_message(portrait_bytes(p, jpeg, alpha, depth)).ok());

  PortraitMessage q = p;
  q.width = 17;  // every image still 16 wide
  expect_rejected(portrait_bytes(q, jpeg, alpha, depth), DecodeErrorKind::BadImage, "color JPEG is 16x12, declared 17x12");
  q = p;
  q.width = 0;
  expect_rejected(portrait_bytes(q, jpeg, alpha, depth), DecodeErrorKind::BadValue, "size 0x12");
  q = p;
  q.height = 5000;
  expect_rejected(portrait_bytes(q, jpeg, alpha, depth), DecodeErrorKind::BadValue, "outside 1..4096");
  q = p;
  q.fx = -1;
  expect_rejected(portrait_bytes(q, jpeg, alpha, depth), DecodeErrorKind::BadValue, "focal length");
  q = p;
  q.camera_from_site(0, 0) = std::nan("");
  expect_rejected(portrait_bytes(q, jpeg, alpha, depth), DecodeErrorKind::BadValue, "not finite");
  q = p;
  q.camera_from_site(0, 0) = 2.0;
  expect_rejected(portrait_bytes(q, jpeg, alpha, depth), DecodeErrorKind::BadValue, "not a rigid transform");

  // A portrait of another size than the receiver displays: refused before any image is decoded
  // (a key holder cannot make the receiver decode 4096x4096 images for a 32x18 display).
  DecodeOptions display;
  display.portrait_width = 32;
  display.portrait_height = 18;
  const DecodeResult other_size = decode_message(portrait_bytes(p, jpeg, alpha, depth), display);
  REQUIRE_FALSE(other_size.ok());
  CHECK(other_size.error.kind == DecodeErrorKind::BadValue);
  CHECK_THAT(other_size.error.message, Catch::Contains("portrait is 16x12, this site displays 32x18 (not decoded)"));
  display.portrait_width = 16;
  display.portrait_height = 12;
  CHECK(decode_message(portrait_bytes(p, jpeg, alpha, depth), display).ok());

  // Images of another size than declared.
  const PortraitMessage small = test::test_portrait(16, 11, 3);
  expect_rejected(portrait_bytes(p, jpeg, alpha, encode_float_plane_png(small.depth, 0, 1)), DecodeErrorKind::BadImage,
                  "depth PNG is 16x44, declared 16x12");
  // Corrupt images.
  auto broken = jpeg;
  broken.resize(broken.size() / 2);
  expect_rejected(portrait_bytes(p, broken, alpha, depth), DecodeErrorKind::BadImage, "EOI");
  broken = jpeg;
  broken[0] = 0;
  expect_rejected(portrait_bytes(p, broken, alpha, depth), DecodeErrorKind::BadImage, "SOI");
  broken = depth;
  broken[broken.size() / 2] ^= 0x5A;  // inside the image data: the chunk CRC fails
  expect_rejected(portrait_bytes(p, jpeg, alpha, broken), DecodeErrorKind::BadImage, "depth: PNG does not decode");
  broken = alpha;
  broken.resize(40);
  expect_rejected(portrait_bytes(p, jpeg, broken, depth), DecodeErrorKind::BadImage, "alpha: PNG does not decode");
  expect_rejected(portrait_bytes(p, jpeg, jpeg, depth), DecodeErrorKind::BadImage, "alpha: not a PNG");
  // Decoded values out of bounds: NaN depth and alpha above 1, losslessly encoded.
  PortraitMessage bad = p;
  bad.depth.at(2, 2) = std::nanf("");
  expect_rejected(portrait_bytes(p, jpeg, alpha, encode_float_plane_png(bad.depth, 0, 1)), DecodeErrorKind::BadValue,
                  "depth nan");
  bad = p;
  bad.color.at(1, 1, 3) = 1.5f;
  expect_rejected(portrait_bytes(p, jpeg, encode_float_plane_png(bad.color, 3, 1), depth), DecodeErrorKind::BadValue,
                  "alpha 1.5");
  // A blob length past the end, and bytes after the last blob.
  auto bytes = portrait_bytes(p, jpeg, alpha, depth);
  patch_u32(bytes, kHeaderSize + 184, uint32_t(bytes.size()));
  expect_rejected(bytes, DecodeErrorKind::Truncated, "color JPEG declares");
  bytes = portrait_bytes(p, jpeg, alpha, depth);
  bytes.push_back(1);
  patch_u32(bytes, 8, uint32_t(bytes.size() - kHeaderSize));
  expect_rejected(bytes, DecodeErrorKind::TrailingBytes, "after the portrait's depth PNG");
}

TEST_CASE("random corruptions of valid messages never crash the decoder") {
  std::vector<std::vector<uint8_t>> seeds = {encode_message(EyeMessage{1, {0.1, 0.2, 0.3}, true}),
                                             encode_message(test::test_skeleton(10)),
                                             encode_message(HeartbeatMessage{1, 2}),
                                             encode_message(test::test_portrait(8, 6, 1)),
                                             encode_message(VoiceMessage{5, 6, 960, std::vector<uint8_t>(60, 0x5a)})};
  std::mt19937 random(7);
  int accepted = 0, rejected = 0;
  for (int i = 0; i < 3000; ++i) {
    auto bytes = seeds[size_t(i) % seeds.size()];
    const int flips = 1 + int(random() % 4);
    for (int f = 0; f < flips; ++f) bytes[random() % bytes.size()] = uint8_t(random());
    if (random() % 4 == 0) bytes.resize(random() % bytes.size());
    const DecodeResult result = decode_message(bytes);
    (result.ok() ? accepted : rejected)++;
    if (!result.ok()) REQUIRE_FALSE(result.error.message.empty());
  }
  INFO(accepted << " accepted, " << rejected << " rejected");
  CHECK(rejected > 1000);
}

TEST_CASE("voice frames round-trip; bad sizes and an unknown type are refused") {
  VoiceMessage voice{123456789, 41, 960, {}};
  for (int i = 0; i < 77; ++i) voice.packet.push_back(uint8_t(i * 13));
  const auto back = round_trip<VoiceMessage>(voice);
  CHECK(back.timestamp_us == voice.timestamp_us);
  CHECK(back.sequence == 41);
  CHECK(back.frame_samples == 960);
  CHECK(back.packet == voice.packet);
  CHECK(message_type(voice) == MessageType::Voice);

  // The sender learns first: no packet, a packet longer than Opus makes, a frame Opus cannot be.
  CHECK_THROWS_WITH(encode_message(VoiceMessage{1, 0, 960, {}}), Catch::Contains("voice packet of 0 bytes"));
  CHECK_THROWS_WITH(encode_message(VoiceMessage{1, 0, 960, std::vector<uint8_t>(kMaxVoicePacket + 1)}),
                    Catch::Contains("must be 1..1275"));
  CHECK_THROWS_WITH(encode_message(VoiceMessage{1, 0, 1000, {1}}), Catch::Contains("must be 480, 960 or 1920"));

  const auto good = encode_message(voice);
  constexpr size_t frame_samples_at = kHeaderSize + 8 + 4, length_at = frame_samples_at + 2;
  auto bytes = good;
  bytes[frame_samples_at] = 7;
  expect_rejected(bytes, DecodeErrorKind::BadValue, "must be 480, 960 or 1920");
  bytes = good;
  bytes[length_at] = 78;  // one more than follows
  expect_rejected(bytes, DecodeErrorKind::BadLength, "declares 78 bytes, 77 follow");
  bytes = good;
  bytes[length_at] = 0;
  expect_rejected(bytes, DecodeErrorKind::BadValue, "voice packet of 0 bytes");
  bytes = good;
  patch_u32(bytes, 8, uint32_t(16 + kMaxVoicePacket + 1));
  expect_rejected(bytes, DecodeErrorKind::BadLength, "limit 1291");
  expect_rejected(std::vector<uint8_t>(good.begin(), good.begin() + kHeaderSize + 10), DecodeErrorKind::Truncated, "");
  bytes = good;
  bytes[6] = 8;
  expect_rejected(bytes, DecodeErrorKind::UnknownType, "unknown message type 8");
}
