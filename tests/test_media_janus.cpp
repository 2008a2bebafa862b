// Janus as the rendezvous and the SFU (media/janus_room.h): the URL's checks here; the calls
// through a real Janus ([.janus], run by ctest through tests/cli/in_network_namespace.sh) in a
// network namespace the test made, where Janus's ICE has an address that is not loopback.
#include <catch2/catch.hpp>

#include <asio.hpp>

#include <chrono>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "janus_in_namespace.h"
#include "media/janus_room.h"
#include "media/portrait_quality.h"
#include "media/synthetic_portrait.h"
#include "media/webrtc_peer.h"
#include "net_test_messages.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::media;

TEST_CASE("a Janus URL is ws://HOST:PORT, anything else is refused with the reason", "[media][janus]") {
  const JanusUrl url = parse_janus_url("ws://janus.example.org:8188");
  CHECK(url.host == "janus.example.org");
  CHECK(url.port == "8188");
  CHECK(url.path == "/");
  CHECK(parse_janus_url("ws://10.0.0.2").port == "8188");
  CHECK(parse_janus_url("ws://10.0.0.2:9000/janus").path == "/janus");
  CHECK_THROWS_WITH(parse_janus_url(""), Catch::Contains("empty"));
  CHECK(parse_janus_url("wss://a:1").tls);
  CHECK(!parse_janus_url("ws://a:1").tls);
  CHECK(parse_janus_url("wss://janus.example.org").port == "8989");
  CHECK_THROWS_WITH(parse_janus_url("http://a:1"), Catch::Contains("scheme 'http'"));
  CHECK_THROWS_WITH(parse_janus_url("ws://a:99999"), Catch::Contains("from 1 to 65535"));
  CHECK_THROWS_WITH(parse_janus_url("ws://a:x"), Catch::Contains("not a URL"));
  CHECK_THROWS_WITH(parse_janus_url("ws://:80"), Catch::Contains("no host"));
  CHECK_THROWS_WITH(parse_janus_url("ws://a b:80"), Catch::Contains("space"));
  CHECK_THROWS_WITH(parse_janus_url("ws://a:80/?x=1"), Catch::Contains("query"));
  CHECK_THROWS_WITH(parse_janus_url(std::string(2000, 'a')), Catch::Contains("longer than"));
}

TEST_CASE("no Janus at the address: the room says it cannot connect", "[media][janus]") {
  JanusRoomOptions o;
  o.url = "ws://127.0.0.1:1";
  o.room = 7;
  o.display = "A";
  o.timeout = std::chrono::milliseconds(2000);
  CHECK_THROWS_WITH(JanusRoom(o), Catch::Contains("cannot connect to 127.0.0.1:1"));
  o.room = 0;
  CHECK_THROWS_WITH(JanusRoom(o), Catch::Contains("room number"));
}

TEST_CASE("wss://: a server that does not speak TLS, or an authorities' file that cannot be read, is refused saying so", "[media][janus]") {
  // A plain TCP listener that accepts and says nothing in TLS.
  asio::io_context io;
  asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), 0});
  const uint16_t port = acceptor.local_endpoint().port();
  std::thread server([&] {
    asio::ip::tcp::socket peer(io);
    asio::error_code ec;
    acceptor.accept(peer, ec);
    if (!ec) asio::write(peer, asio::buffer(std::string("HTTP/1.1 400 Bad Request\r\n\r\n")), ec);
  });
  JanusRoomOptions o;
  o.url = "wss://127.0.0.1:" + std::to_string(port);
  o.room = 7;
  o.display = "A";
  o.timeout = std::chrono::milliseconds(3000);
  CHECK_THROWS_WITH(JanusRoom(o), Catch::Contains("no TLS with 127.0.0.1:" + std::to_string(port)));
  server.join();
  o.ca_file = "/nonexistent/janus-ca.pem";
  CHECK_THROWS_WITH(JanusRoom(o), Catch::Contains("--janus-ca /nonexistent/janus-ca.pem: cannot be read"));
}

namespace {

// One site in the room: its publisher and subscriber peers and their signalling through Janus.
// The peers' callbacks (GStreamer's threads) queue descriptions; pump() hands them to Janus on
// the test's thread, since Janus's answers take a round trip.
struct JanusTestSite {
  JanusTestSite(const std::string& url, const std::string& name, const std::string& address, uint32_t width, uint32_t height,
                std::shared_ptr<ChannelGuard> guard) {
    JanusRoomOptions o;
    o.url = url;
    o.room = 4242;
    o.pin = "test-pin";
    o.display = name;
    room = std::make_unique<JanusRoom>(o);
    id = room->join();
    options.name = name;
    options.width = width;
    options.height = height;
    options.color_kbps = 1500;
    options.depth_kbps = 800;
    options.local_addresses = {address};
    options.max_queued_portraits = 64;
    options.relayed = true;
    options.guard = std::move(guard);
    WebRtcPeerOptions p = options;
    p.offerer = true;
    publisher = std::make_unique<WebRtcPeer>(p, signalling(JanusRoom::Peer::Publisher));
  }

  media::Signalling signalling(JanusRoom::Peer peer) {
    media::Signalling s;
    s.on_description = [this, peer](const std::string& type, const std::string& sdp) {
      std::lock_guard lock(mutex);
      said.push_back({peer, type, sdp});
    };
    s.on_candidate = [this, peer](unsigned mline, const std::string& candidate) { room->trickle(peer, mline, candidate); };
    return s;
  }

  void pump() {
    std::deque<Said> now;
    {
      std::lock_guard lock(mutex);
      now.swap(said);
    }
    for (const Said& s : now) {
      if (s.peer == JanusRoom::Peer::Publisher && s.type == "offer") {
        const std::string answer = room->publish(s.sdp);
        std::ofstream(test::output_dir("test_media_janus") / ("publisher_" + options.name + ".sdp")) << s.sdp << "\n----\n" << answer;
        const std::string error = publisher->set_remote_description("answer", answer);
        INFO(error);
        REQUIRE(error.empty());
      } else if (s.peer == JanusRoom::Peer::Subscriber && s.type == "answer") {
        room->start(s.sdp);
      }
    }
  }

  void subscribe(uint64_t feed) {
    WebRtcPeerOptions o = options;
    o.offerer = false;
    // Janus relays a subscriber's data nowhere: its handshake frames go out through the publisher.
    o.handshake_out = [this](std::span<const uint8_t> frame) { return publisher->send_handshake(frame); };
    subscriber = std::make_unique<WebRtcPeer>(o, signalling(JanusRoom::Peer::Subscriber));
    const std::string offer = room->subscribe(feed);
    std::ofstream(test::output_dir("test_media_janus") / ("subscriber_offer_" + options.name + ".sdp")) << offer;
    const std::string error = subscriber->set_remote_description("offer", offer);
    INFO(error);
    REQUIRE(error.empty());
  }

  struct Said {
    JanusRoom::Peer peer;
    std::string type, sdp;
  };
  std::unique_ptr<JanusRoom> room;
  uint64_t id = 0;
  WebRtcPeerOptions options;
  std::unique_ptr<WebRtcPeer> publisher, subscriber;
  std::mutex mutex;
  std::deque<Said> said;
};

}  // namespace

TEST_CASE("over wss://, a site joins when Janus's certificate is trusted and is refused saying why when not", "[.janus][media]") {
  std::string why;
  const std::optional<std::string> address = test::janus_test_address(&why);
  if (!address) {
    WARN("SKIPPED: " << why);
    return;
  }
  const std::filesystem::path folder = test::output_dir("test_media_janus_wss");
  test::JanusInNamespace janus(folder, *address);
  REQUIRE(janus.wait_ready(std::chrono::seconds(15)));
  JanusRoomOptions o;
  o.room = 4343;
  o.display = "A";
  o.timeout = std::chrono::milliseconds(5000);
  // Janus's certificate is its own: the system's authorities do not vouch for it.
  o.url = "wss://127.0.0.1:8989";
  CHECK_THROWS_WITH(JanusRoom(o), Catch::Contains("no TLS with 127.0.0.1:8989") && Catch::Contains("self-signed certificate") &&
                                      Catch::Contains("--janus-ca"));
  // Trusted, but not the name the certificate was made for.
  o.ca_file = (folder / "janus-cert.pem").string();
  o.url = "wss://localhost:8989";
  CHECK_THROWS_WITH(JanusRoom(o), Catch::Contains("no TLS with localhost:8989") && Catch::Contains("hostname mismatch"));
  o.url = "wss://127.0.0.1:8989";
  JanusRoom room(o);
  CHECK(room.join() > 0);
  CHECK(room.messages_refused() == 0);
}

TEST_CASE("two sites meet in a Janus room and see each other through it", "[.janus][media]") {
  std::string why;
  const std::optional<std::string> address = test::janus_test_address(&why);
  if (!address) {
    WARN("SKIPPED: " << why);
    return;
  }
  test::JanusInNamespace janus(test::output_dir("test_media_janus"), *address);
  REQUIRE(janus.wait_ready(std::chrono::seconds(15)));
  constexpr uint32_t width = 320, height = 180;
  // The site key seals the data channels end to end, its handshake relayed by Janus like the rest.
  const net::SessionKey key = net::random_session_key();
  JanusTestSite a(janus.url(), "A", *address, width, height, std::make_shared<ChannelGuard>(key, net::Role::Connector, 60000)),
      b(janus.url(), "B", *address, width, height, std::make_shared<ChannelGuard>(key, net::Role::Listener, 60000));
  CHECK(a.id != b.id);
  // The offer needs the tracks' caps, which come with the first portrait.
  a.publisher->send_portrait(synthetic_portrait(width, height, 1000));
  b.publisher->send_portrait(synthetic_portrait(width, height, 1000));
  // Each site publishes (Janus answers its offer), then subscribes to the other once it publishes.
  for (int i = 0; i < 400 && !(a.publisher->channels_up() && b.publisher->channels_up()); ++i) {
    a.pump();
    b.pump();
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  INFO("A: " << a.publisher->last_error() << " / " << a.room->last_error() << "; B: " << b.publisher->last_error() << " / "
             << b.room->last_error());
  const std::optional<uint64_t> a_sees = a.room->wait_for_other(std::chrono::seconds(5));
  const std::optional<uint64_t> b_sees = b.room->wait_for_other(std::chrono::seconds(5));
  REQUIRE(a_sees == b.id);
  REQUIRE(b_sees == a.id);
  a.subscribe(*a_sees);
  b.subscribe(*b_sees);
  // Connected: all four peer connections up and the site key's handshake done across Janus.
  const auto subscribed = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  const auto all_up = [&] {
    return a.publisher->connected() && b.publisher->connected() && a.subscriber->connected() && b.subscriber->connected();
  };
  while (std::chrono::steady_clock::now() < subscribed && !all_up()) {
    a.pump();
    b.pump();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  INFO("A: " << a.subscriber->last_error() << "; B: " << b.subscriber->last_error());
  REQUIRE(all_up());

  // What arrived before both subscriptions were up is not part of the count.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  while (a.subscriber->take_portrait() || b.subscriber->take_portrait()) {
  }
  a.publisher->request_keyframe();
  b.publisher->request_keyframe();
  // Janus starts each subscriber's streams at RTP time zero from the packet it relayed first, so
  // the pictures pair with their records only by the time they carry in their bitstream.
  std::set<uint64_t> at_b, at_a;
  double worst_psnr = 1e9, worst_depth = 0.0, worst_iou = 1.0;
  const auto check = [&](const ReceivedPortrait& r, std::set<uint64_t>& into) {
    const PortraitQuality q = portrait_quality(synthetic_portrait(width, height, r.portrait.frame_index), r.portrait);
    worst_psnr = std::min(worst_psnr, q.psnr_user_db);
    worst_depth = std::max(worst_depth, q.depth_median_error_m);
    worst_iou = std::min(worst_iou, q.silhouette_iou);
    into.insert(r.portrait.frame_index);
  };
  const auto take = [&] {
    while (auto r = b.subscriber->take_portrait()) check(*r, at_b);
    while (auto r = a.subscriber->take_portrait()) check(*r, at_a);
  };
  constexpr uint32_t frames = 60;
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t sent = 0; sent < frames; ++sent) {
    std::this_thread::sleep_until(start + std::chrono::milliseconds(33 * sent));
    a.publisher->send_portrait(synthetic_portrait(width, height, sent));
    b.publisher->send_portrait(synthetic_portrait(width, height, sent));
    if (sent % 10 == 0) {
      CHECK(a.publisher->send_message(net::TouchEventMessage{.timestamp_us = 1000 + sent, .sequence = sent}));
      CHECK(b.publisher->send_message(test::test_skeleton(2000 + sent)));
    }
    a.pump();
    b.pump();
    take();
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while ((at_a.size() < frames || at_b.size() < frames) && std::chrono::steady_clock::now() < deadline) {
    take();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const std::vector<net::Message> at_b_messages = b.subscriber->take_messages(), at_a_messages = a.subscriber->take_messages();
  const WebRtcCounters ca = a.subscriber->counters(), cb = b.subscriber->counters();
  std::printf("janus: portraits A->B %zu, B->A %zu of %u; worst PSNR %.2f dB, depth median %.2f mm, IoU %.4f; messages A->B %zu, "
              "B->A %zu of 6; refused at B %llu at A %llu\n",
              at_b.size(), at_a.size(), frames, worst_psnr, worst_depth * 1e3, worst_iou, at_b_messages.size(), at_a_messages.size(),
              (unsigned long long)cb.messages_refused, (unsigned long long)ca.messages_refused);
  std::printf("janus: at B %llu portraits lost, %llu pictures unpaired, packets lost colour %llu depth %llu, keyframes asked %llu; sent by A "
              "%llu at %d kbit/s\n",
              (unsigned long long)cb.portraits_lost, (unsigned long long)cb.frames_unpaired, (unsigned long long)cb.color_loss.packets_lost, (unsigned long long)cb.depth_loss.packets_lost,
              (unsigned long long)cb.keyframes_asked, (unsigned long long)a.publisher->counters().portraits_sent,
              a.publisher->counters().color_kbps_now);
  INFO("A: " << a.subscriber->last_error() << "; B: " << b.subscriber->last_error());
  // Loopback inside the namespace loses nothing: every portrait and message comes through, as
  // good as the codecs make a portrait this small (eight of them run here at once, on CI's two
  // cores: at 640x360 they fell behind, Janus or not).
  CHECK(at_b.size() == frames);
  CHECK(at_a.size() == frames);
  CHECK(worst_psnr >= 34.0);
  CHECK(worst_depth <= 0.003);
  CHECK(worst_iou >= 0.99);
  CHECK(at_b_messages.size() == 6);
  CHECK(at_a_messages.size() == 6);
  CHECK(cb.messages_refused + ca.messages_refused == 0);
  // Both streams come under one payload type of Janus's: each told apart by what it decodes to.
  CHECK(cb.color_decode_ms > 0);
  CHECK(cb.depth_decode_ms > 0);
  CHECK(a.room->messages_refused() + b.room->messages_refused() == 0);
}
