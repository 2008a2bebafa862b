// The depth/alpha luma of the WebRTC link (media/depth_alpha_codec.h) and the portrait frame
// record (media/portrait_frame.h): quantization within half a code, the reserved empty code and
// its threshold, clamping, refusals of bad ranges and malformed records; and the quality measure
// the link's test relies on, shown to catch a decoder that uses the wrong range.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "media/depth_alpha_codec.h"
#include "media/portrait_frame.h"
#include "media/portrait_quality.h"
#include "media/synthetic_portrait.h"

using namespace rt;
using namespace rt::media;

TEST_CASE("depth codes are within half a step over the working range", "[media]") {
  const DepthRange range;
  REQUIRE(range.step_m() < 0.0018);
  double worst = 0.0;
  for (double d = range.near_m; d <= range.far_m; d += 0.000377) {
    const uint16_t code = encode_depth_alpha(float(d), 1.0f, range);
    REQUIRE(code >= kDepthCodeMin);
    REQUIRE(code <= kDepthCodeMax);
    float depth = 0.0f, alpha = 0.0f;
    decode_depth_alpha(code, range, depth, alpha);
    REQUIRE(alpha == 1.0f);
    worst = std::max(worst, std::abs(double(depth) - d));
  }
  CHECK(worst <= range.step_m() / 2 + 1e-6);
}

TEST_CASE("empty pixels take the reserved code, and the threshold tells them apart", "[media]") {
  const DepthRange range;
  CHECK(encode_depth_alpha(1.2f, 0.0f, range) == kEmptyCode);
  CHECK(encode_depth_alpha(1.2f, 0.49f, range) == kEmptyCode);
  CHECK(encode_depth_alpha(1.2f, std::nanf(""), range) == kEmptyCode);
  // The user's pixel without a measured depth stays the user's, at the near end.
  CHECK(encode_depth_alpha(0.0f, 1.0f, range) == kDepthCodeMin);
  CHECK(encode_depth_alpha(std::nanf(""), 1.0f, range) == kDepthCodeMin);
  // Outside the range: clamped.
  CHECK(encode_depth_alpha(0.1f, 1.0f, range) == kDepthCodeMin);
  CHECK(encode_depth_alpha(9.0f, 1.0f, range) == kDepthCodeMax);
  float depth = -1.0f, alpha = -1.0f;
  decode_depth_alpha(kAlphaThreshold - 1, range, depth, alpha);
  CHECK((depth == 0.0f && alpha == 0.0f));
  // Ringing between the threshold and the first depth code is the user at the near end.
  decode_depth_alpha(kAlphaThreshold, range, depth, alpha);
  CHECK((alpha == 1.0f && depth == float(range.near_m)));
  // A codec's ringing of +-40 codes on either side of the silhouette does not cross the threshold.
  CHECK(int(kEmptyCode) + 40 < int(kAlphaThreshold));
  CHECK(int(kDepthCodeMin) - 40 >= int(kAlphaThreshold));
}

TEST_CASE("bad depth ranges are refused with the reason", "[media]") {
  CHECK(check_depth_range({0.4, 2.0}).empty());
  CHECK_THAT(check_depth_range({0.0, 2.0}), Catch::Contains("near end"));
  CHECK_THAT(check_depth_range({1.0, 1.0}), Catch::Contains("far end"));
  CHECK_THAT(check_depth_range({std::nan(""), 1.0}), Catch::Contains("not finite"));
}

TEST_CASE("a plane round trip keeps the silhouette and the depth, and refuses a short plane", "[media]") {
  const net::PortraitMessage sent = synthetic_portrait(64, 36, 3);
  const DepthRange range;
  std::vector<uint16_t> luma(70 * 36);
  encode_depth_alpha_plane(sent.color, sent.depth, range, luma, 70);
  net::PortraitMessage received = sent;
  decode_depth_alpha_plane(luma, 70, range, received.color, received.depth);
  const PortraitQuality q = portrait_quality(sent, received);
  CHECK(q.user_pixels > 200);
  CHECK(q.silhouette_iou == 1.0);
  CHECK(q.depth_median_error_m <= range.step_m() / 2 + 1e-6);
  CHECK(q.all_finite);
  std::vector<uint16_t> short_plane(64 * 35);
  CHECK_THROWS_AS(encode_depth_alpha_plane(sent.color, sent.depth, range, short_plane, 64), std::invalid_argument);
  CHECK_THROWS_AS(decode_depth_alpha_plane(short_plane, 64, range, received.color, received.depth), std::invalid_argument);
}

TEST_CASE("the quality measure catches a decoder on the wrong depth range or a lost silhouette", "[media]") {
  const net::PortraitMessage sent = synthetic_portrait(64, 36, 5);
  std::vector<uint16_t> luma(64 * 36);
  encode_depth_alpha_plane(sent.color, sent.depth, DepthRange{}, luma, 64);
  net::PortraitMessage received = sent;
  decode_depth_alpha_plane(luma, 64, DepthRange{0.4, 2.1}, received.color, received.depth);
  CHECK(portrait_quality(sent, received).depth_median_error_m > 0.002);
  std::fill(luma.begin(), luma.begin() + long(luma.size() / 2), kEmptyCode);  // the head lost
  decode_depth_alpha_plane(luma, 64, DepthRange{}, received.color, received.depth);
  CHECK(portrait_quality(sent, received).silhouette_iou < 0.99);
  received.depth.at(3, 3) = std::nanf("");
  CHECK_FALSE(portrait_quality(sent, received).all_finite);
}

TEST_CASE("the portrait frame record round-trips and refuses what is malformed", "[media]") {
  PortraitFrame f;
  f.rtp_timestamp = 0xfedcba98u;
  f.frame_index = 77;
  f.capture_timestamp_us = 123456789;
  f.width = 1280;
  f.height = 720;
  f.fx = 1152.5;
  f.fy = 1151.25;
  f.cx = 640.25;
  f.cy = 288.75;
  f.camera_from_site(0, 3) = 0.125;
  f.depth_range = {0.5, 1.75};
  const std::vector<uint8_t> bytes = encode_portrait_frame(f);
  REQUIRE(bytes.size() == kPortraitFrameSize);
  std::string why;
  const auto back = decode_portrait_frame(bytes, 1280, 720, &why);
  REQUIRE(back);
  CHECK(back->rtp_timestamp == f.rtp_timestamp);
  CHECK(back->frame_index == 77);
  CHECK(back->capture_timestamp_us == 123456789);
  CHECK(back->cy == 288.75);
  CHECK(back->camera_from_site(0, 3) == 0.125);
  CHECK(back->depth_range.far_m == 1.75);

  const auto refused = [&](std::vector<uint8_t> b, uint32_t w, uint32_t h, const char* mentions) {
    std::string reason;
    CHECK_FALSE(decode_portrait_frame(b, w, h, &reason));
    CHECK_THAT(reason, Catch::Contains(mentions));
  };
  refused({bytes.begin(), bytes.end() - 1}, 1280, 720, "bytes, expected");
  refused({}, 1280, 720, "bytes, expected");
  refused(bytes, 640, 360, "the link carries 640x360");
  auto bad = bytes;
  bad[0] = 'X';
  refused(bad, 1280, 720, "magic");
  bad = bytes;
  bad[4] = 9;
  refused(bad, 1280, 720, "version 9");
  bad = bytes;
  const double nan = std::nan("");
  std::memcpy(bad.data() + 36, &nan, 8);  // fx
  refused(bad, 1280, 720, "not finite");
  bad = bytes;
  const double backwards = 0.1;
  std::memcpy(bad.data() + kPortraitFrameSize - 8, &backwards, 8);  // far before near
  refused(bad, 1280, 720, "far end");
}
