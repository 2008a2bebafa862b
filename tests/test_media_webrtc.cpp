// Two WebRTC peers in one process over loopback (127.0.0.1 only; the offer, answer and candidates
// handed across in-process): portraits of a simulated user cross as H.264 colour and 10-bit
// depth/alpha and come out paired and within the stated tolerances; the session's messages cross
// on their data channels; bad input (a malformed SDP, a wrong-size portrait, data-channel bytes
// that fail the session's checks) is refused with a reason and the call goes on.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <thread>

#include "media/portrait_frame.h"
#include "media/portrait_quality.h"
#include "media/synthetic_portrait.h"
#include "media/webrtc_peer.h"
#include "webrtc_loopback_call.h"
#include "net_test_messages.h"
#include "time/monotonic_clock.h"

using namespace rt;
using namespace rt::media;
using rt::test::LoopbackWebRtcCall;

namespace {

template <typename T>
std::vector<T> messages_of(const std::vector<net::Message>& messages) {
  std::vector<T> out;
  for (const net::Message& m : messages)
    if (std::holds_alternative<T>(m)) out.push_back(std::get<T>(m));
  return out;
}

}  // namespace

TEST_CASE("portraits cross a loopback WebRTC call paired and within tolerance", "[media][webrtc]") {
  constexpr uint32_t width = 640, height = 360, frames = 30;
  LoopbackWebRtcCall call(width, height);
  REQUIRE(call.connect(width, height));
  // Only loopback candidates were offered: nothing is sent anywhere else.
  REQUIRE_FALSE(call.candidates.empty());
  for (const std::string& candidate : call.candidates) {
    INFO(candidate);
    CHECK(candidate.find(" 127.0.0.1 ") != std::string::npos);
  }
  // What arrived before the call was up (the first portrait) is not part of the count.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  while (call.answerer->take_portrait()) {
  }
  call.offerer->request_keyframe();

  std::set<uint64_t> received;
  double worst_psnr = 1e9, worst_depth = 0.0, worst_iou = 1.0, sum_depth = 0.0;
  bool finite = true;
  const auto check = [&](const ReceivedPortrait& r) {
    const net::PortraitMessage sent = synthetic_portrait(width, height, r.portrait.frame_index);
    const PortraitQuality q = portrait_quality(sent, r.portrait);
    worst_psnr = std::min(worst_psnr, q.psnr_user_db);
    worst_depth = std::max(worst_depth, q.depth_median_error_m);
    sum_depth += q.depth_median_error_m;
    worst_iou = std::min(worst_iou, q.silhouette_iou);
    finite = finite && q.all_finite && q.user_pixels > 20000;
    CHECK(r.portrait.fx == sent.fx);
    CHECK(r.portrait.cy == sent.cy);
    received.insert(r.portrait.frame_index);
  };
  const WebRtcCounters before = call.offerer->counters();
  const uint64_t start = monotonic_now_us();
  for (uint32_t i = 0; i < frames; ++i) {
    while (monotonic_now_us() < start + uint64_t(i) * 33'333) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    call.offerer->send_portrait(synthetic_portrait(width, height, i));
    call.pump();
    while (auto r = call.answerer->take_portrait()) check(*r);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (received.size() < frames && std::chrono::steady_clock::now() < deadline) {
    if (auto r = call.answerer->take_portrait()) check(*r);
    else std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const WebRtcCounters after = call.offerer->counters();
  std::printf("colour %.0f kbit/s depth %.0f kbit/s worst psnr %.2f depth %.2f mm mean %.2f iou %.4f\n",
              double(after.color_bytes_sent - before.color_bytes_sent) * 8 / 1000 / (frames / 30.0),
              double(after.depth_bytes_sent - before.depth_bytes_sent) * 8 / 1000 / (frames / 30.0), worst_psnr, worst_depth * 1e3,
              sum_depth / double(std::max<size_t>(1, received.size())) * 1e3, worst_iou);
  INFO("A: " << call.offerer->last_error() << "; B: " << call.answerer->last_error());
  INFO("worst PSNR " << worst_psnr << " dB, worst depth median error " << worst_depth * 1e3 << " mm (mean "
                     << sum_depth / double(std::max<size_t>(1, received.size())) * 1e3 << "), worst IoU "
                     << worst_iou);
  // Every portrait came through with its colour, its depth and its record paired.
  CHECK(received.size() == frames);
  CHECK((!received.empty() && *received.rbegin() == frames - 1));
  CHECK(worst_psnr >= 36.0);
  CHECK(worst_depth <= 0.002);
  CHECK(worst_iou >= 0.99);
  CHECK(finite);
  CHECK(call.answerer->counters().portraits_dropped == 0);
}

TEST_CASE("the session's messages cross the data channels, and bad input is refused", "[media][webrtc]") {
  constexpr uint32_t width = 320, height = 180;
  LoopbackWebRtcCall call(width, height);
  REQUIRE(call.connect(width, height));
  WebRtcPeer& a = *call.offerer;
  WebRtcPeer& b = *call.answerer;

  net::EyeMessage eye;
  eye.timestamp_us = 42;
  eye.eye = {0.01, 0.02, 0.7};
  eye.valid = true;
  net::TouchEventMessage touch;
  touch.timestamp_us = 43;
  touch.site = 1;
  touch.sender_session = 99;
  touch.sequence = 1;
  net::HeartbeatMessage heartbeat;
  heartbeat.sequence = 5;
  REQUIRE(a.send_message(eye));
  REQUIRE(a.send_message(test::test_skeleton(44)));
  REQUIRE(a.send_message(touch));
  REQUIRE(a.send_message(heartbeat));
  // The other way too: the answerer's channels are the same two.
  REQUIRE(b.send_message(heartbeat));
  CHECK_THROWS_AS(a.send_message(synthetic_portrait(width, height, 0)), std::invalid_argument);

  std::vector<net::Message> at_b, at_a;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while ((at_b.size() < 4 || at_a.empty()) && std::chrono::steady_clock::now() < deadline) {
    for (auto& m : b.take_messages()) at_b.push_back(std::move(m));
    for (auto& m : a.take_messages()) at_a.push_back(std::move(m));
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  REQUIRE(at_b.size() == 4);
  REQUIRE(at_a.size() == 1);
  REQUIRE(messages_of<net::EyeMessage>(at_b).size() == 1);
  CHECK(messages_of<net::EyeMessage>(at_b)[0].eye.z() == 0.7);
  REQUIRE(messages_of<net::SkeletonMessage>(at_b).size() == 1);
  CHECK(messages_of<net::SkeletonMessage>(at_b)[0].hands.size() == 2);
  REQUIRE(messages_of<net::TouchEventMessage>(at_b).size() == 1);
  CHECK(messages_of<net::TouchEventMessage>(at_b)[0].sequence == 1);
  CHECK(messages_of<net::HeartbeatMessage>(at_a).size() == 1);

  // Bytes that fail the session's checks: refused one by one with the reason, nothing delivered.
  const auto refused_with = [&](WebRtcPeer::Channel channel, std::vector<uint8_t> bytes, const char* mentions) {
    const uint64_t before = b.counters().messages_refused;
    REQUIRE(a.send_raw(channel, bytes));
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (b.counters().messages_refused == before && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    CHECK(b.counters().messages_refused == before + 1);
    CHECK_THAT(b.last_error(), Catch::Contains(mentions));
    CHECK(b.take_messages().empty());
  };
  refused_with(WebRtcPeer::Channel::Reliable, {'n', 'o', 'n', 's', 'e', 'n', 's', 'e', 0, 0, 0, 0, 1}, "refused");
  std::vector<uint8_t> skeleton = net::encode_message(test::test_skeleton(45));
  refused_with(WebRtcPeer::Channel::Reliable, skeleton, "wrong data channel");
  skeleton.back() ^= 0xff;  // truncation or a bad value: the codec says which
  skeleton.pop_back();
  refused_with(WebRtcPeer::Channel::Fast, skeleton, "refused");
  PortraitFrame frame;
  frame.width = width;
  frame.height = height;
  frame.fx = frame.fy = 100;
  std::vector<uint8_t> record = encode_portrait_frame(frame);
  record.push_back(0);
  refused_with(WebRtcPeer::Channel::Fast, record, "portrait frame record");
  CHECK_FALSE(a.send_raw(WebRtcPeer::Channel::Fast, std::vector<uint8_t>(70 * 1024, 7)));
  // The call still works after all that.
  REQUIRE(a.send_message(touch));
  const auto again = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  std::vector<net::Message> late;
  while (late.empty() && std::chrono::steady_clock::now() < again) {
    late = b.take_messages();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  CHECK(late.size() == 1);

  // A portrait of the wrong size, and descriptions that cannot be used.
  CHECK_THROWS_WITH(a.send_portrait(synthetic_portrait(width + 2, height, 0)), Catch::Contains("this link carries 320x180"));
  CHECK_THAT(b.set_remote_description("offer", "hello"), Catch::Contains("malformed"));
  CHECK_THAT(b.set_remote_description("offer", "v=0\r\nthis is not sdp\r\n"), Catch::Contains("malformed"));
  CHECK_THAT(b.set_remote_description("pranswer", "v=0\r\n"), Catch::Contains("expected offer or answer"));
  CHECK_THAT(a.set_remote_description("offer", "v=0\r\n"), Catch::Contains("offer given to the peer that makes the offer"));
  CHECK_THAT(b.set_remote_description("offer", std::string(300 * 1024, 'v')), Catch::Contains("over the limit"));
}

TEST_CASE("a WebRTC peer refuses sizes the tracks cannot carry", "[media][webrtc]") {
  WebRtcPeerOptions options;
  options.width = 641;
  CHECK_THROWS_WITH(WebRtcPeer(options, {}), Catch::Contains("even sizes"));
  options.width = 640;
  options.depth_range = {2.0, 1.0};
  CHECK_THROWS_WITH(WebRtcPeer(options, {}), Catch::Contains("far end"));
  options.depth_range = {};
  options.local_addresses = {"not-an-address"};
  CHECK_THROWS_WITH(WebRtcPeer(options, {}), Catch::Contains("not an IP address"));
}

TEST_CASE("the answerer's portraits reach the offerer on the same call", "[media][webrtc]") {
  // One webrtcbin per remote peer carries both directions: the answerer's two tracks take the
  // offer's two sendrecv transceivers.
  constexpr uint32_t width = 320, height = 180, frames = 30;
  LoopbackWebRtcCall call(width, height);
  REQUIRE(call.connect(width, height));
  std::set<uint64_t> received;
  double worst_iou = 1.0;
  const auto take = [&] {
    while (auto r = call.offerer->take_portrait()) {
      received.insert(r->portrait.frame_index);
      worst_iou = std::min(worst_iou, portrait_quality(synthetic_portrait(width, height, r->portrait.frame_index), r->portrait).silhouette_iou);
    }
  };
  const uint64_t start = monotonic_now_us();
  for (uint32_t i = 0; i < frames; ++i) {
    while (monotonic_now_us() < start + uint64_t(i) * 33'333) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    call.answerer->send_portrait(synthetic_portrait(width, height, i));
    call.pump();
    take();
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (received.size() < frames && std::chrono::steady_clock::now() < deadline) {
    take();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  INFO("A: " << call.offerer->last_error() << "; B: " << call.answerer->last_error());
  CHECK(received.size() == frames);
  CHECK(worst_iou >= 0.99);
}

TEST_CASE("with the site key on the data channels, sealed messages and portraits cross; clear bytes do not",
          "[media][webrtc]") {
  constexpr uint32_t width = 160, height = 90;
  const net::SessionKey key = net::random_session_key();
  constexpr size_t limit = 64 * 1024 - net::kDatagramOverhead;
  auto guard_a = std::make_shared<ChannelGuard>(key, net::Role::Connector, limit);
  auto guard_b = std::make_shared<ChannelGuard>(key, net::Role::Listener, limit);
  LoopbackWebRtcCall call(width, height, guard_a, guard_b);
  REQUIRE(call.connect(width, height));
  REQUIRE(guard_a->ready());
  REQUIRE(guard_b->ready());
  net::TouchEventMessage touch;
  touch.timestamp_us = 5;
  touch.sequence = 1;
  REQUIRE(call.offerer->send_message(touch));
  REQUIRE(call.answerer->send_message(net::EyeMessage{7, Eigen::Vector3d(0, 0.1, 0.7), true}));
  // Bytes in the clear, even a well-formed message, are refused: only the key's records open.
  const std::vector<uint8_t> clear = net::encode_message(net::HeartbeatMessage{1, 2});
  const uint64_t refused_before = call.answerer->counters().messages_refused;
  REQUIRE(call.offerer->send_raw(WebRtcPeer::Channel::Reliable, clear));  // sealed by the guard: accepted
  std::vector<net::Message> at_b, at_a;
  size_t portraits = 0;
  // Portraits keep coming, as in a call: where a loaded machine loses the first pictures, a sender
  // that had stopped would never send the keyframe the receiver asks for.
  uint32_t sent = 0;
  auto next_portrait = std::chrono::steady_clock::now();
  const auto deadline = next_portrait + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline && (at_b.size() < 2 || at_a.empty() || portraits < 3)) {
    if (std::chrono::steady_clock::now() >= next_portrait) {
      call.offerer->send_portrait(synthetic_portrait(width, height, 2000 + sent++));
      next_portrait += std::chrono::milliseconds(34);
    }
    call.pump();
    for (auto& m : call.answerer->take_messages()) at_b.push_back(std::move(m));
    for (auto& m : call.offerer->take_messages()) at_a.push_back(std::move(m));
    while (call.answerer->take_portrait()) ++portraits;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  CHECK(messages_of<net::TouchEventMessage>(at_b).size() == 1);
  CHECK(messages_of<net::HeartbeatMessage>(at_b).size() == 1);
  CHECK(messages_of<net::EyeMessage>(at_a).size() == 1);
  INFO(sent << " portraits sent for " << portraits << " received");
  CHECK(portraits >= 3);  // the frame records were sealed and opened too
  CHECK(call.answerer->counters().messages_refused == refused_before);
}

TEST_CASE("two sites with different keys never open their data channels to each other", "[media][webrtc]") {
  constexpr uint32_t width = 160, height = 90;
  constexpr size_t limit = 64 * 1024 - net::kDatagramOverhead;
  auto guard_a = std::make_shared<ChannelGuard>(net::random_session_key(), net::Role::Connector, limit);
  auto guard_b = std::make_shared<ChannelGuard>(net::random_session_key(), net::Role::Listener, limit);
  LoopbackWebRtcCall call(width, height, guard_a, guard_b);
  CHECK_FALSE(call.connect(width, height, std::chrono::seconds(4)));
  CHECK(guard_b->failure().find("different keys") != std::string::npos);
  CHECK_FALSE(guard_a->ready());
  CHECK_FALSE(call.offerer->send_message(net::EyeMessage{7, Eigen::Vector3d(0, 0.1, 0.7), true}));
}
