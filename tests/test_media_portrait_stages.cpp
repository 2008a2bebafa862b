// Where a tiny portrait loses over the WebRTC link against the direct session's (JPEG colour,
// lossless alpha): each stage of the link alone and together, on the synthetic user at the demo's
// size (96x54, its forearm about five pixels wide), scored as the demo scores the hand at the glass:
// colour premultiplied by alpha (over black), over every pixel either portrait covers, so a soft
// edge made hard counts as what the viewer sees. Prints the figures of each stage.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <map>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "media/depth_alpha_codec.h"
#include "media/portrait_pictures.h"
#include "media/synthetic_portrait.h"
#include "net/image_codec.h"
#include "webrtc_loopback_call.h"

using namespace rt;
using namespace rt::media;
using rt::test::LoopbackWebRtcCall;

namespace {

// Squared error of premultiplied RGB, pooled over frames; the region is where either covers.
struct PremultipliedError {
  double squared = 0.0;
  size_t samples = 0;
  void add(const HostImage& sent, const HostImage& shown, uint32_t x_from) {
    for (uint32_t y = 0; y < sent.height; ++y)
      for (uint32_t x = x_from; x < sent.width; ++x) {
        const float a = std::clamp(sent.at(x, y, 3), 0.0f, 1.0f), b = std::clamp(shown.at(x, y, 3), 0.0f, 1.0f);
        if (a == 0.0f && b == 0.0f) continue;
        for (uint32_t c = 0; c < 3; ++c) {
          const double d = double(std::clamp(shown.at(x, y, c), 0.0f, 1.0f)) * b - double(std::clamp(sent.at(x, y, c), 0.0f, 1.0f)) * a;
          squared += d * d;
          ++samples;
        }
      }
  }
  double psnr_db() const { return samples ? 10.0 * std::log10(double(samples) / std::max(squared, 1e-12)) : 0.0; }
};

// The user and the forearm alone (the right third of the synthetic portrait holds only the arm).
struct StageScore {
  PremultipliedError user, forearm;
  void add(const HostImage& sent, const HostImage& shown) {
    user.add(sent, shown, 0);
    forearm.add(sent, shown, sent.width * 2 / 3);
  }
};

HostImage through_jpeg(const HostImage& color, int quality) {
  HostImage out = color;
  const std::vector<uint8_t> jpeg = net::encode_color_jpeg(color, quality);
  REQUIRE_FALSE(net::decode_color_jpeg(jpeg, out).has_value());
  return out;
}

// 8-bit BT.601 I420 and back, as the colour track's pictures are made and read (no codec).
HostImage through_i420(const HostImage& color) {
  cv::Mat rgb(int(color.height), int(color.width), CV_8UC3);
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x)
      for (uint32_t c = 0; c < 3; ++c)
        rgb.at<cv::Vec3b>(int(y), int(x))[int(c)] = uint8_t(std::clamp(color.at(x, y, c), 0.0f, 1.0f) * 255.0f + 0.5f);
  cv::Mat yuv, back;
  cv::cvtColor(rgb, yuv, cv::COLOR_RGB2YUV_I420);
  cv::cvtColor(yuv, back, cv::COLOR_YUV2RGB_I420);
  HostImage out = color;
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x)
      for (uint32_t c = 0; c < 3; ++c) out.at(x, y, c) = float(back.at<cv::Vec3b>(int(y), int(x))[int(c)]) / 255.0f;
  return out;
}

// The depth/alpha track's codes alone (no codec): the portrait as the receiver decodes them.
net::PortraitMessage through_depth_alpha_codes(const net::PortraitMessage& sent) {
  std::vector<uint16_t> luma(size_t(sent.width) * sent.height), alpha(luma.size());
  encode_depth_alpha_plane(sent.color, sent.depth, DepthRange{}, luma, alpha, sent.width);
  net::PortraitMessage out = sent;
  decode_depth_alpha_plane(luma, alpha, sent.width, DepthRange{}, out.color, out.depth);
  return out;
}

// The luma's silhouette alone, as the track carried alpha before its alpha plane: hard at 0.5,
// colour dropped where empty.
HostImage with_hard_alpha(HostImage color) {
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x) {
      float depth = 0.0f, alpha = 0.0f;
      decode_depth_alpha(encode_depth_alpha(1.0f, color.at(x, y, 3), DepthRange{}), DepthRange{}, depth, alpha);
      color.at(x, y, 3) = alpha;
      if (alpha == 0.0f)
        for (uint32_t c = 0; c < 3; ++c) color.at(x, y, c) = 0.0f;
    }
  return color;
}

HostImage with_alpha_of(HostImage color, const HostImage& alpha_from) {
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x) color.at(x, y, 3) = alpha_from.at(x, y, 3);
  return color;
}

HostImage with_colour_of(HostImage alpha_from, const HostImage& color) {
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x)
      for (uint32_t c = 0; c < 3; ++c) alpha_from.at(x, y, c) = color.at(x, y, c);
  return alpha_from;
}

}  // namespace

TEST_CASE("at the demo's size the WebRTC portrait's stages each lose what they lose, against the direct session's",
          "[media][webrtc]") {
  constexpr uint32_t width = 96, height = 54, frames = 30;
  // The site's rates (site_run: the colour starts at its ceiling).
  LoopbackWebRtcCall call(width, height, nullptr, nullptr, [](WebRtcPeerOptions& o) {
    o.color_kbps = 2500;
    o.depth_kbps = 1200;
  });
  REQUIRE(call.connect(width, height));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  while (call.answerer->take_portrait()) {
  }
  call.offerer->request_keyframe();

  std::map<std::string, StageScore> stages;
  size_t received = 0;
  const auto score = [&](const ReceivedPortrait& r) {
    const net::PortraitMessage sent = synthetic_portrait(width, height, r.portrait.frame_index);
    stages["webrtc"].add(sent.color, r.portrait.color);
    stages["webrtc colour, sent alpha"].add(sent.color, with_alpha_of(r.portrait.color, sent.color));
    stages["webrtc alpha, sent colour"].add(sent.color, with_colour_of(r.portrait.color, sent.color));
    ++received;
  };
  for (uint32_t i = 0; i < frames; ++i) {
    const net::PortraitMessage sent = synthetic_portrait(width, height, i);
    stages["direct (JPEG 90)"].add(sent.color, through_jpeg(sent.color, 90));
    stages["I420 alone"].add(sent.color, through_i420(sent.color));
    stages["depth/alpha codes alone"].add(sent.color, through_depth_alpha_codes(sent).color);
    stages["hard alpha alone"].add(sent.color, with_hard_alpha(sent.color));
    call.offerer->send_portrait(sent);
    call.pump();
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
    while (auto r = call.answerer->take_portrait()) score(*r);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (received < frames && std::chrono::steady_clock::now() < deadline) {
    if (auto r = call.answerer->take_portrait()) score(*r);
    else std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  REQUIRE(received >= frames - 2);
  for (const auto& [name, s] : stages)
    std::printf("%-28s premultiplied PSNR: user %.2f dB, forearm %.2f dB\n", name.c_str(), s.user.psnr_db(), s.forearm.psnr_db());
  // The measure sees a hard edge (what the link cost before its alpha plane), and the link now
  // loses no more than the direct session on the user or the forearm.
  const StageScore& direct = stages["direct (JPEG 90)"];
  CHECK(stages["hard alpha alone"].forearm.psnr_db() < direct.forearm.psnr_db() - 6.0);
  CHECK(stages["webrtc"].user.psnr_db() >= direct.user.psnr_db() - 0.5);
  CHECK(stages["webrtc"].forearm.psnr_db() >= direct.forearm.psnr_db() - 0.5);
  CHECK(stages["webrtc alpha, sent colour"].forearm.psnr_db() >= 40.0);
}

TEST_CASE("the hard edge costs less as the portrait grows", "[media]") {
  // No codec: the luma's hard silhouette against the direct session's JPEG, premultiplied over the
  // user, at the sizes the link carries; the synthetic edge is a pixel and a half wide at every size.
  double previous_hard = 0.0;
  for (const auto& [w, h] : {std::pair{96u, 54u}, {320u, 180u}, {640u, 360u}, {1280u, 720u}}) {
    StageScore hard, jpeg;
    for (uint64_t frame = 0; frame < 5; ++frame) {
      const net::PortraitMessage sent = synthetic_portrait(w, h, frame);
      hard.add(sent.color, with_hard_alpha(sent.color));
      jpeg.add(sent.color, through_jpeg(sent.color, 90));
    }
    std::printf("%ux%u: premultiplied PSNR over the user, hard edge %.2f dB, JPEG 90 %.2f dB\n", w, h, hard.user.psnr_db(),
                jpeg.user.psnr_db());
    CHECK(hard.user.psnr_db() > previous_hard);
    CHECK(hard.user.psnr_db() < jpeg.user.psnr_db());
    previous_hard = hard.user.psnr_db();
  }
}

TEST_CASE("the depth/alpha picture carries the soft edge up to its size limit, and a hard one beyond", "[media]") {
  gst_init(nullptr, nullptr);
  const auto soft_codes = [](uint32_t w, uint32_t h) {
    const net::PortraitMessage p = synthetic_portrait(w, h, 7);
    GstBuffer* buffer = make_depth_alpha_picture(p.color, p.depth, DepthRange{}, w, h);
    GstVideoInfo info;
    gst_video_info_set_format(&info, GST_VIDEO_FORMAT_Y444_10LE, w, h);
    GstVideoFrame frame;
    REQUIRE(gst_video_frame_map(&frame, &info, buffer, GST_MAP_READ));
    const DepthAlphaCodes codes = codes_of_depth_alpha_picture(frame, w, h);
    gst_video_frame_unmap(&frame);
    gst_buffer_unref(buffer);
    return size_t(std::count_if(codes.alpha.begin(), codes.alpha.end(), [](uint16_t c) { return c > kAlphaSnapCodes; }));
  };
  CHECK(soft_codes(96, 54) > 100);
  CHECK(soft_codes(320, 180) > 500);
  CHECK(soft_codes(322, 180) == 0);
  CHECK(soft_codes(640, 360) == 0);
}
