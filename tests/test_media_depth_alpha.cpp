// The depth/alpha luma of the WebRTC link (media/depth_alpha_codec.h) and the portrait frame
// record (media/portrait_frame.h): quantization within half a code, the reserved empty code and
// its threshold, clamping, refusals of bad ranges and malformed records; and the quality measure
// the link's test relies on, shown to catch a decoder that uses the wrong range.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "media/depth_alpha_codec.h"
#include "media/portrait_frame.h"
#include "media/portrait_quality.h"
#include "media/synthetic_portrait.h"

using namespace rt;
using namespace rt::media;

namespace {
// Half a step of the alpha plane's codes (0..0.5 over kAlphaCodeMax codes), and float rounding.
constexpr float kAlphaHalfStep = 0.25f / kAlphaCodeMax + 1e-6f;
}  // namespace

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

TEST_CASE("a plane round trip keeps the silhouette, the depth and the soft edge, and refuses a short plane", "[media]") {
  const net::PortraitMessage sent = synthetic_portrait(64, 36, 3);
  const DepthRange range;
  std::vector<uint16_t> luma(70 * 36), alpha(70 * 36);
  encode_depth_alpha_plane(sent.color, sent.depth, range, luma, alpha, 70);
  net::PortraitMessage received = sent;
  decode_depth_alpha_plane(luma, alpha, 70, range, received.color, received.depth);
  const PortraitQuality q = portrait_quality(sent, received);
  CHECK(q.user_pixels > 200);
  CHECK(q.silhouette_iou == 1.0);
  CHECK(q.depth_median_error_m <= range.step_m() / 2 + 1e-6);
  CHECK(q.all_finite);
  // The soft edge comes back within half an alpha code (the synthetic edge is a pixel and a half
  // wide, every soft pixel beside the user); its colour is kept.
  size_t soft = 0;
  for (uint32_t y = 0; y < 36; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      const float a = sent.color.at(x, y, 3);
      if (encode_alpha(a) <= kAlphaSnapCodes) continue;
      ++soft;
      INFO("pixel " << x << "," << y << " alpha " << a);
      CHECK(std::abs(received.color.at(x, y, 3) - a) <= kAlphaHalfStep);
      CHECK(received.color.at(x, y, 0) == sent.color.at(x, y, 0));
      CHECK(received.depth.at(x, y) > 0.0f);
    }
  CHECK(soft > 50);
  std::vector<uint16_t> short_plane(64 * 35);
  CHECK_THROWS_AS(encode_depth_alpha_plane(sent.color, sent.depth, range, short_plane, alpha, 64), std::invalid_argument);
  CHECK_THROWS_AS(encode_depth_alpha_plane(sent.color, sent.depth, range, luma, short_plane, 64), std::invalid_argument);
  CHECK_THROWS_AS(decode_depth_alpha_plane(short_plane, alpha, 64, range, received.color, received.depth), std::invalid_argument);
  CHECK_THROWS_AS(decode_depth_alpha_plane(luma, short_plane, 64, range, received.color, received.depth), std::invalid_argument);
}

TEST_CASE("the alpha plane codes the distance from the luma's decision, and decodes within that decision", "[media]") {
  CHECK(encode_alpha(0.0f) == 0);
  CHECK(encode_alpha(1.0f) == 0);
  CHECK(encode_alpha(2.0f) == 0);
  CHECK(encode_alpha(-1.0f) == 0);
  CHECK(encode_alpha(std::nanf("")) == 0);
  const uint16_t quarter = uint16_t(std::lround(0.5 * kAlphaCodeMax));
  CHECK(encode_alpha(0.25f) == quarter);  // 0.25 off empty
  CHECK(encode_alpha(0.75f) == quarter);  // 0.25 off the user
  CHECK(encode_alpha(0.49f) == uint16_t(std::lround(0.98 * kAlphaCodeMax)));
  CHECK(encode_alpha(0.5f) == kAlphaCodeMax);
  const uint16_t user = kDepthCodeMin + 100;
  // The user: within [0.5, 1]; the codec's noise near 0 is the whole user.
  CHECK(decode_alpha(user, 0) == 1.0f);
  CHECK(decode_alpha(user, kAlphaSnapCodes) == 1.0f);
  CHECK(decode_alpha(user, quarter) == Approx(0.75f).margin(0.001));
  CHECK(decode_alpha(user, kAlphaCodeMax) == 0.5f);
  CHECK(decode_alpha(user, 4000) == 0.5f);  // beyond 10 bits
  // Empty: within [0, 0.5); the codec's noise near 0 is empty.
  CHECK(decode_alpha(kEmptyCode, 0) == 0.0f);
  CHECK(decode_alpha(kEmptyCode, kAlphaSnapCodes) == 0.0f);
  CHECK(decode_alpha(kEmptyCode, quarter) == Approx(0.25f).margin(0.001));
  CHECK(decode_alpha(kEmptyCode, kAlphaCodeMax) < 0.5f);
  CHECK(decode_alpha(kAlphaThreshold - 1, kAlphaCodeMax) < 0.5f);
  CHECK(decode_alpha(kAlphaThreshold, kAlphaCodeMax) == 0.5f);
}

TEST_CASE("a soft pixel away from the silhouette is dropped, one beside it takes the nearest depth", "[media]") {
  // 5x3: user pixels at (1,1) 1.0 m and (2,1) 1.2 m; soft matte at (3,1), beside the user, and at
  // (4,0), beside nothing but (3,1), itself soft.
  HostImage color(5, 3, PixelFormat::RGBA32F), depth(5, 3, PixelFormat::R32F);
  for (uint32_t y = 0; y < 3; ++y)
    for (uint32_t x = 0; x < 5; ++x)
      for (uint32_t c = 0; c < 3; ++c) color.at(x, y, c) = 0.5f;
  color.at(1, 1, 3) = 1.0f, depth.at(1, 1) = 1.0f;
  color.at(2, 1, 3) = 0.8f, depth.at(2, 1) = 1.2f;
  color.at(3, 1, 3) = 0.3f, depth.at(3, 1) = std::nanf("");
  color.at(4, 0, 3) = 0.3f, depth.at(4, 0) = 1.1f;
  std::vector<uint16_t> luma(15), alpha(15);
  const DepthRange range;
  encode_depth_alpha_plane(color, depth, range, luma, alpha, 5);
  CHECK(luma[1 * 5 + 3] == kEmptyCode);
  HostImage color_out(5, 3, PixelFormat::RGBA32F), depth_out(5, 3, PixelFormat::R32F);
  for (float& v : color_out.texels) v = 0.5f;
  decode_depth_alpha_plane(luma, alpha, 5, range, color_out, depth_out);
  CHECK(color_out.at(1, 1, 3) == 1.0f);
  CHECK(color_out.at(2, 1, 3) == Approx(0.8f).margin(0.001));
  CHECK(color_out.at(3, 1, 3) == Approx(0.3f).margin(0.001));
  CHECK(depth_out.at(3, 1) == Approx(1.2f).margin(range.step_m()));  // its only user neighbour
  CHECK(color_out.at(3, 1, 0) == 0.5f);
  CHECK(color_out.at(4, 0, 3) == 0.0f);  // no user beside it: the codec's noise, dropped
  CHECK(depth_out.at(4, 0) == 0.0f);
  CHECK(color_out.at(4, 0, 0) == 0.0f);
  CHECK(color_out.at(0, 0, 3) == 0.0f);
  // Beside two users, the nearer's depth (the edge belongs to the surface in front).
  color.at(2, 2, 3) = 0.2f;
  encode_depth_alpha_plane(color, depth, range, luma, alpha, 5);
  decode_depth_alpha_plane(luma, alpha, 5, range, color_out, depth_out);
  CHECK(depth_out.at(2, 2) == Approx(1.0f).margin(range.step_m()));
}

TEST_CASE("planes of random odd sizes round-trip within half a code, NaN and out-of-range values included", "[media]") {
  std::mt19937 random(48);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const DepthRange range{0.5, 1.8};
  for (int round = 0; round < 20; ++round) {
    const uint32_t w = 1 + 2 * (random() % 40), h = 1 + 2 * (random() % 25);
    const size_t stride = w + random() % 7;
    HostImage color(w, h, PixelFormat::RGBA32F), depth(w, h, PixelFormat::R32F);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const float pick = unit(random);
        // Whole user, empty, soft, NaN alpha, alpha beyond 1; depth in range, NaN, 0, out of range.
        color.at(x, y, 3) = pick < 0.4f ? 1.0f : pick < 0.6f ? 0.0f : pick < 0.9f ? unit(random) : pick < 0.95f ? std::nanf("") : 1.5f;
        const float d = unit(random);
        depth.at(x, y) = d < 0.8f ? 0.5f + 1.3f * unit(random) : d < 0.87f ? std::nanf("") : d < 0.93f ? 0.0f : 3.0f;
        for (uint32_t c = 0; c < 3; ++c) color.at(x, y, c) = unit(random);
      }
    std::vector<uint16_t> luma(stride * h), alpha(stride * h);
    encode_depth_alpha_plane(color, depth, range, luma, alpha, stride);
    HostImage color_out = color, depth_out(w, h, PixelFormat::R32F);
    decode_depth_alpha_plane(luma, alpha, stride, range, color_out, depth_out);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        INFO(w << "x" << h << " pixel " << x << "," << y << " alpha " << color.at(x, y, 3) << " depth " << depth.at(x, y));
        const float a = color.at(x, y, 3), out = color_out.at(x, y, 3), d = depth_out.at(x, y);
        REQUIRE(std::isfinite(out));
        REQUIRE(std::isfinite(d));
        if (a >= 0.5f) {  // the user, at its depth clamped to the range (the near end unmeasured)
          CHECK(out == Approx(std::min(a, 1.0f)).margin(float(kAlphaSnapCodes + 1) / (2 * kAlphaCodeMax)));
          const float measured = std::isfinite(depth.at(x, y)) && depth.at(x, y) > 0.0f ? depth.at(x, y) : float(range.near_m);
          CHECK(d == Approx(std::clamp(measured, float(range.near_m), float(range.far_m))).margin(range.step_m() / 2 + 1e-5));
          continue;
        }
        bool beside_user = false;
        for (uint32_t ny = y ? y - 1 : 0; ny <= std::min(y + 1, h - 1); ++ny)
          for (uint32_t nx = x ? x - 1 : 0; nx <= std::min(x + 1, w - 1); ++nx) beside_user |= color.at(nx, ny, 3) >= 0.5f;
        const bool soft = encode_alpha(a) > kAlphaSnapCodes;  // false for NaN
        CHECK((out > 0.0f) == (soft && beside_user));
        if (out > 0.0f) {  // soft, beside the user, at a user's depth, its colour kept
          CHECK(out == Approx(a).margin(kAlphaHalfStep));
          CHECK(d >= float(range.near_m) - 1e-5f);
          CHECK(d <= float(range.far_m) + 1e-5f);
          CHECK(color_out.at(x, y, 0) == color.at(x, y, 0));
        } else {  // empty: no depth, no colour
          CHECK(d == 0.0f);
          CHECK(color_out.at(x, y, 0) == 0.0f);
        }
      }
  }
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
