// The site key on the data channels, without GStreamer: the handshake over the reliable channel,
// then sealed records both ways on both channels; a wrong key, a replayed record, a record on the
// other channel, a handshake frame on the fast channel and clear bytes are refused.
#include <catch2/catch.hpp>

#include <memory>
#include <string>
#include <vector>

#include "media/channel_guard.h"

using namespace rt;
using namespace rt::media;

namespace {

constexpr size_t kGuardTestLimit = 4096;

// Hands each side's reply to the other until neither has anything to say.
void run_guard_handshake(ChannelGuard& connector, ChannelGuard& listener) {
  std::vector<uint8_t> frame = connector.start();
  REQUIRE_FALSE(frame.empty());
  CHECK(listener.start().empty());  // the listener answers, it does not begin
  CHECK(connector.start().empty());  // not again within a quarter second
  bool to_listener = true;
  for (int step = 0; step < 4 && !frame.empty(); ++step) {
    ChannelGuard::Received got = (to_listener ? listener : connector).receive(GuardedChannel::Reliable, frame);
    if (got.kind == ChannelGuard::Received::Kind::Refused) {
      frame = got.reply;
    } else {
      REQUIRE(got.kind == ChannelGuard::Received::Kind::Handshake);
      frame = got.reply;
    }
    to_listener = !to_listener;
  }
}

std::vector<uint8_t> guard_bytes(const std::string& text) { return std::vector<uint8_t>(text.begin(), text.end()); }

}  // namespace

TEST_CASE("the guards' handshake gives both sides keys, and records cross both ways on both channels") {
  const net::SessionKey key = net::random_session_key();
  ChannelGuard connector(key, net::Role::Connector, kGuardTestLimit), listener(key, net::Role::Listener, kGuardTestLimit);
  CHECK_FALSE(connector.seal(GuardedChannel::Fast, guard_bytes("early")));  // nothing goes out before the keys
  run_guard_handshake(connector, listener);
  REQUIRE(connector.ready());
  REQUIRE(listener.ready());
  for (const GuardedChannel channel : {GuardedChannel::Fast, GuardedChannel::Reliable}) {
    const auto there = connector.seal(channel, guard_bytes("skeleton"));
    REQUIRE(there);
    const auto opened = listener.receive(channel, *there);
    REQUIRE(opened.kind == ChannelGuard::Received::Kind::Message);
    CHECK(opened.message == guard_bytes("skeleton"));
    const auto back = listener.seal(channel, guard_bytes("eye"));
    REQUIRE(back);
    CHECK(connector.receive(channel, *back).message == guard_bytes("eye"));
    // The same record again: refused (the fast channel's window, the reliable channel's order).
    const auto again = listener.receive(channel, *there);
    CHECK(again.kind == ChannelGuard::Received::Kind::Refused);
    CHECK(again.reason.find("refused") != std::string::npos);
  }
  // A record of one channel does not open on the other; nor does a record of our own (reflected).
  const auto fast = connector.seal(GuardedChannel::Fast, guard_bytes("touch?"));
  CHECK(listener.receive(GuardedChannel::Reliable, *fast).kind == ChannelGuard::Received::Kind::Refused);
  CHECK(connector.receive(GuardedChannel::Fast, *fast).kind == ChannelGuard::Received::Kind::Refused);
  // Clear bytes and handshake frames once done are refused.
  CHECK(listener.receive(GuardedChannel::Reliable, guard_bytes("RTNM plain")).kind == ChannelGuard::Received::Kind::Refused);
  CHECK(listener.receive(GuardedChannel::Reliable, connector.start()).kind == ChannelGuard::Received::Kind::Refused);
}

TEST_CASE("guards with different keys refuse each other, and nothing is sealed") {
  ChannelGuard connector(net::random_session_key(), net::Role::Connector, kGuardTestLimit);
  ChannelGuard listener(net::random_session_key(), net::Role::Listener, kGuardTestLimit);
  run_guard_handshake(connector, listener);
  CHECK_FALSE(connector.ready());
  CHECK_FALSE(listener.ready());
  CHECK(listener.failure().find("different keys") != std::string::npos);
  CHECK_FALSE(listener.seal(GuardedChannel::Reliable, guard_bytes("touch")));
}

TEST_CASE("the guards drop a record that overtook the handshake's last frame, and open the next") {
  const net::SessionKey key = net::random_session_key();
  ChannelGuard connector(key, net::Role::Connector, kGuardTestLimit), listener(key, net::Role::Listener, kGuardTestLimit);
  const auto listener_hello = listener.receive(GuardedChannel::Reliable, connector.start());
  REQUIRE(listener_hello.kind == ChannelGuard::Received::Kind::Handshake);
  const auto connector_proof = connector.receive(GuardedChannel::Reliable, listener_hello.reply);
  REQUIRE(connector_proof.kind == ChannelGuard::Received::Kind::Handshake);
  const auto listener_proof = listener.receive(GuardedChannel::Reliable, connector_proof.reply);
  REQUIRE(listener_proof.kind == ChannelGuard::Received::Kind::Handshake);
  REQUIRE(listener.ready());
  REQUIRE_FALSE(connector.ready());
  // The listener's first skeleton, on the fast channel, before its proof on the reliable one.
  const auto first = listener.seal(GuardedChannel::Fast, guard_bytes("skeleton 1"));
  REQUIRE(first);
  const auto early = connector.receive(GuardedChannel::Fast, *first);
  CHECK(early.kind == ChannelGuard::Received::Kind::Early);
  CHECK(early.message.empty());
  REQUIRE(connector.receive(GuardedChannel::Reliable, listener_proof.reply).kind == ChannelGuard::Received::Kind::Handshake);
  REQUIRE(connector.ready());
  const auto second = listener.seal(GuardedChannel::Fast, guard_bytes("skeleton 2"));
  const auto opened = connector.receive(GuardedChannel::Fast, *second);
  REQUIRE(opened.kind == ChannelGuard::Received::Kind::Message);
  CHECK(opened.message == guard_bytes("skeleton 2"));
}

TEST_CASE("the guards' handshake refuses frames out of place") {
  const net::SessionKey key = net::random_session_key();
  {
    ChannelGuard connector(key, net::Role::Connector, kGuardTestLimit), listener(key, net::Role::Listener, kGuardTestLimit);
    const auto hello = connector.start();
    const auto on_fast = listener.receive(GuardedChannel::Fast, hello);
    CHECK(on_fast.kind == ChannelGuard::Received::Kind::Refused);
    CHECK(on_fast.reason.find("rt-fast") != std::string::npos);
    CHECK(listener.receive(GuardedChannel::Reliable, std::span(hello).first(40)).kind == ChannelGuard::Received::Kind::Refused);
  }
  {
    ChannelGuard connector(key, net::Role::Connector, kGuardTestLimit), listener(key, net::Role::Listener, kGuardTestLimit);
    const auto hello = connector.start();
    const auto answer = listener.receive(GuardedChannel::Reliable, hello);
    REQUIRE(answer.kind == ChannelGuard::Received::Kind::Handshake);
    // The same hello again (sent before the answer came, which a relay may have dropped) gets the
    // same answer again.
    const auto again = listener.receive(GuardedChannel::Reliable, hello);
    CHECK(again.kind == ChannelGuard::Received::Kind::Handshake);
    CHECK(again.reply == answer.reply);
    // The connector takes the answer once and a repeat of it as already taken, then completes.
    const auto proof = connector.receive(GuardedChannel::Reliable, answer.reply);
    REQUIRE(proof.kind == ChannelGuard::Received::Kind::Handshake);
    CHECK_FALSE(proof.reply.empty());
    const auto repeat = connector.receive(GuardedChannel::Reliable, again.reply);
    CHECK(repeat.kind == ChannelGuard::Received::Kind::Handshake);
    CHECK(repeat.reply.empty());
    CHECK(connector.failure().empty());
    const auto last = listener.receive(GuardedChannel::Reliable, proof.reply);
    CHECK(connector.receive(GuardedChannel::Reliable, last.reply).kind == ChannelGuard::Received::Kind::Handshake);
    CHECK(connector.ready());
    CHECK(listener.ready());
  }
  {
    // Another connector's hello after the first: refused.
    ChannelGuard connector(key, net::Role::Connector, kGuardTestLimit), listener(key, net::Role::Listener, kGuardTestLimit);
    REQUIRE(listener.receive(GuardedChannel::Reliable, connector.start()).kind == ChannelGuard::Received::Kind::Handshake);
    ChannelGuard other(key, net::Role::Connector, kGuardTestLimit);
    CHECK(listener.receive(GuardedChannel::Reliable, other.start()).reason == "a second hello");
  }
  {
    // A connector's hello sent to a connector (a reflection) is refused by its role byte.
    ChannelGuard one(key, net::Role::Connector, kGuardTestLimit), other(key, net::Role::Connector, kGuardTestLimit);
    (void)other.start();
    CHECK(other.receive(GuardedChannel::Reliable, one.start()).kind == ChannelGuard::Received::Kind::Refused);
  }
  {
    ChannelGuard listener(key, net::Role::Listener, kGuardTestLimit);
    std::vector<uint8_t> frame = guard_bytes("RTDH");
    frame.push_back(9);
    CHECK(listener.receive(GuardedChannel::Reliable, frame).reason.find("unknown step") != std::string::npos);
  }
}

TEST_CASE("a guard reset after the other site left runs a new handshake with the site that comes back, and nothing of the last call opens") {
  const net::SessionKey key = net::random_session_key();
  ChannelGuard staying(key, net::Role::Connector, kGuardTestLimit);
  auto departed = std::make_unique<ChannelGuard>(key, net::Role::Listener, kGuardTestLimit);
  run_guard_handshake(staying, *departed);
  REQUIRE(staying.ready());
  const auto old_record = departed->seal(GuardedChannel::Reliable, guard_bytes("touch of the last call"));
  REQUIRE(old_record);
  departed.reset();  // the other site's process ends; a new one starts with the same key

  ChannelGuard returning(key, net::Role::Listener, kGuardTestLimit);
  // Without a reset the staying side would refuse the new call's handshake and have nothing to send.
  staying.reset();
  CHECK(staying.resets() == 1);
  CHECK_FALSE(staying.ready());
  CHECK_FALSE(staying.seal(GuardedChannel::Reliable, guard_bytes("before the new keys")));
  run_guard_handshake(staying, returning);
  REQUIRE(staying.ready());
  REQUIRE(returning.ready());
  // The new call's records number from the start and open; the last call's do not.
  const auto fresh = returning.seal(GuardedChannel::Reliable, guard_bytes("touch"));
  REQUIRE(fresh);
  const auto opened = staying.receive(GuardedChannel::Reliable, *fresh);
  REQUIRE(opened.kind == ChannelGuard::Received::Kind::Message);
  CHECK(opened.message == guard_bytes("touch"));
  CHECK(staying.receive(GuardedChannel::Reliable, *old_record).kind == ChannelGuard::Received::Kind::Refused);
  const auto there = staying.seal(GuardedChannel::Fast, guard_bytes("skeleton"));
  CHECK(returning.receive(GuardedChannel::Fast, *there).message == guard_bytes("skeleton"));
}

TEST_CASE("a listener reset after the connector left takes the restarted connector's hello and refuses the old one replayed") {
  const net::SessionKey key = net::random_session_key();
  ChannelGuard staying(key, net::Role::Listener, kGuardTestLimit);
  ChannelGuard departed(key, net::Role::Connector, kGuardTestLimit);
  const std::vector<uint8_t> old_hello = departed.start();
  REQUIRE_FALSE(old_hello.empty());
  const auto answer = staying.receive(GuardedChannel::Reliable, old_hello);
  const auto proof = departed.receive(GuardedChannel::Reliable, answer.reply);
  const auto last = staying.receive(GuardedChannel::Reliable, proof.reply);
  departed.receive(GuardedChannel::Reliable, last.reply);
  REQUIRE(staying.ready());
  REQUIRE(departed.ready());
  staying.reset();
  // A relay that kept the departed connector's hello cannot start a call with it...
  ChannelGuard::Received replayed = staying.receive(GuardedChannel::Reliable, old_hello);
  CHECK(replayed.kind == ChannelGuard::Received::Kind::Refused);
  CHECK(replayed.reason.find("replayed") != std::string::npos);
  // ...which fails this handshake; the next reset (the relay's site gone) lets the real one in.
  staying.reset();
  CHECK(staying.failure().empty());
  ChannelGuard returning(key, net::Role::Connector, kGuardTestLimit);
  run_guard_handshake(returning, staying);
  REQUIRE(staying.ready());
  REQUIRE(returning.ready());
  const auto touch = returning.seal(GuardedChannel::Reliable, guard_bytes("touch"));
  CHECK(staying.receive(GuardedChannel::Reliable, *touch).message == guard_bytes("touch"));
}
