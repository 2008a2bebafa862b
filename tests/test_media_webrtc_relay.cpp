// A relay-only WebRTC call (ice-transport-policy relay) through a coturn `turnserver` the test
// starts on 127.0.0.1 on free ports: both peers gather relay candidates only, the call connects
// through the relay and thirty portraits cross it. Skipped, saying so, where turnserver is not installed
// (scripts/packages.txt lists coturn, so CI has it).
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <asio.hpp>
#include <chrono>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "media/ice_servers.h"
#include "media/synthetic_portrait.h"
#include "support/output_dir.h"
#include "webrtc_loopback_call.h"

using namespace rt;
using namespace rt::media;
using rt::test::LoopbackWebRtcCall;

namespace {

constexpr const char* kTurnServer = "/usr/bin/turnserver";

// A UDP port nobody holds now (the kernel's choice); the relay's ports follow it.
uint16_t free_udp_port() {
  asio::io_context io;
  asio::ip::udp::socket socket(io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  return socket.local_endpoint().port();
}

// coturn on loopback for the test's life: long-term credentials, no TLS, loopback peers allowed.
class LoopbackTurnServer {
 public:
  LoopbackTurnServer(const std::filesystem::path& folder, uint16_t port, uint16_t relay_low) {
    std::filesystem::create_directories(folder);
    const std::vector<std::string> args = {kTurnServer, "-n", "--listening-ip", "127.0.0.1", "--relay-ip", "127.0.0.1",
                                           "--listening-port", std::to_string(port), "--min-port", std::to_string(relay_low),
                                           "--max-port", std::to_string(relay_low + 50), "--allow-loopback-peers",
                                           "--no-tls", "--no-dtls", "--no-cli", "-a", "-u", "rt:relay-secret", "-r",
                                           "remotetouch", "--userdb", (folder / "turndb").string(), "--log-file",
                                           (folder / "turnserver.log").string(), "--simple-log", "--no-stdout-log",
                                           "--pidfile", (folder / "turnserver.pid").string()};
    std::filesystem::remove(folder / "turndb");
    pid_ = fork();
    if (pid_ == 0) {
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(kTurnServer, argv.data());
      _exit(127);
    }
  }
  ~LoopbackTurnServer() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  bool running() {
    int status = 0;
    return pid_ > 0 && waitpid(pid_, &status, WNOHANG) == 0;
  }

 private:
  pid_t pid_ = -1;
};

}  // namespace

TEST_CASE("a relay-only call connects through a TURN server on loopback", "[media][webrtc][turn]") {
  if (!std::filesystem::exists(kTurnServer)) {
    WARN("SKIPPED: " << kTurnServer << " is missing: apt-get install coturn (scripts/packages.txt lists it)");
    return;
  }
  const uint16_t port = free_udp_port();
  const uint16_t relay_low = uint16_t(40000 + port % 20000);
  LoopbackTurnServer turn(test::output_dir("test_media_webrtc_relay"), port, relay_low);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // its listener up
  REQUIRE(turn.running());
  const std::string url = parse_turn_url("turn://rt:relay-secret@127.0.0.1:" + std::to_string(port));
  constexpr uint32_t width = 320, height = 180;
  LoopbackWebRtcCall call(width, height, nullptr, nullptr, [&](WebRtcPeerOptions& o) {
    o.turn_server = url;
    o.relay_only = true;
  });
  REQUIRE(call.connect(width, height, std::chrono::seconds(20)));
  // Only relay candidates went across: the call could go no other way.
  REQUIRE_FALSE(call.candidates.empty());
  for (const std::string& candidate : call.candidates) {
    INFO(candidate);
    CHECK(candidate.find(" typ relay") != std::string::npos);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  while (call.answerer->take_portrait()) {
  }
  // Thirty portraits must come through; up to three seconds of them are sent (the relay's first
  // keyframe can be lost to a loaded machine and asked again).
  std::set<uint64_t> received;
  const auto start = std::chrono::steady_clock::now();
  uint32_t sent = 0;
  for (; sent < 90 && received.size() < 30; ++sent) {
    std::this_thread::sleep_until(start + std::chrono::milliseconds(33 * sent));
    call.offerer->send_portrait(synthetic_portrait(width, height, sent));
    call.pump();
    while (auto r = call.answerer->take_portrait()) received.insert(r->portrait.frame_index);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (received.size() < 30 && std::chrono::steady_clock::now() < deadline) {
    if (auto r = call.answerer->take_portrait()) received.insert(r->portrait.frame_index);
    else std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  INFO("A: " << call.offerer->last_error() << "; B: " << call.answerer->last_error());
  std::printf("relay: %zu portraits of %u sent through the TURN relay on port %u\n", received.size(), sent, unsigned(port));
  CHECK(received.size() >= 30);
}

TEST_CASE("a relay-only call without a TURN server is refused", "[media][webrtc][turn]") {
  WebRtcPeerOptions o;
  o.width = 64;
  o.height = 64;
  o.relay_only = true;
  CHECK_THROWS_WITH(WebRtcPeer(o, Signalling{}), Catch::Contains("needs a TURN server"));
}
