#include "media/channel_guard.h"

#include <sodium.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace rt::media {
namespace {

constexpr uint8_t kGuardHandshakeMagic[4] = {'R', 'T', 'D', 'H'};
constexpr uint8_t kGuardStepHello = 1, kGuardStepProof = 2;

std::vector<uint8_t> guard_frame(uint8_t step, std::span<const uint8_t> payload) {
  std::vector<uint8_t> frame(sizeof(kGuardHandshakeMagic) + 1 + payload.size());
  std::memcpy(frame.data(), kGuardHandshakeMagic, sizeof(kGuardHandshakeMagic));
  frame[sizeof(kGuardHandshakeMagic)] = step;
  if (!payload.empty()) std::memcpy(frame.data() + sizeof(kGuardHandshakeMagic) + 1, payload.data(), payload.size());
  return frame;
}

const char* guard_channel_name(GuardedChannel channel) { return channel == GuardedChannel::Fast ? "rt-fast" : "rt-reliable"; }

}  // namespace

ChannelGuard::ChannelGuard(const net::SessionKey& key, net::Role role, size_t max_message)
    : key_(key), role_(role), max_message_(max_message), gate_(key), handshake_(std::make_unique<net::Handshake>(key, role)) {
  if (net::is_weak_session_key(key)) throw std::invalid_argument("the site key is too regular to be a secret: make one with `remotetouch keygen`");
}

ChannelGuard::~ChannelGuard() = default;

std::vector<uint8_t> ChannelGuard::start() {
  std::lock_guard lock(mutex_);
  if (role_ != net::Role::Connector || hello_seen_ || !failure_.empty()) return {};
  // Again until the listener answers: a hello that reached the other side before its end of the
  // channel had a reader is gone, and nothing else would start the handshake again.
  const auto now = std::chrono::steady_clock::now();
  if (started_ && now - last_start_ < std::chrono::milliseconds(250)) return {};
  started_ = true;
  last_start_ = now;
  return guard_frame(kGuardStepHello, handshake_->hello());
}

void ChannelGuard::reset() {
  std::lock_guard lock(mutex_);
  // What must not carry over, and why:
  // - the traffic keys and the sealers' sequence numbers: the returning site holds neither (its
  //   process is new), and records sealed under the old keys again would let a relay replay the
  //   last call's touches into this one;
  // - the openers' replay windows and strict order: the new keys number their records from the
  //   start, which the old windows would refuse as replays;
  // - the handshake's nonce and ephemeral secret: fresh ones give the new keys no tie to the old
  //   (each call has forward secrecy of its own), and a handshake object answers one peer only;
  // - a failure: the site that failed (another key) may not be the one that comes next.
  // The hello gate's last accepted time stays: a relay replaying the departed connector's hello
  // to this listener is refused, while a new connector's hello is later and passes.
  handshake_ = std::make_unique<net::Handshake>(key_, role_);
  started_ = hello_seen_ = false;
  last_start_ = {};
  peer_hello_.fill(0);
  failure_.clear();
  seal_fast_.reset();
  seal_reliable_.reset();
  open_fast_.reset();
  open_reliable_.reset();
  ++resets_;
}

uint64_t ChannelGuard::resets() const {
  std::lock_guard lock(mutex_);
  return resets_;
}

bool ChannelGuard::ready() const {
  std::lock_guard lock(mutex_);
  return seal_fast_ != nullptr;
}

std::string ChannelGuard::failure() const {
  std::lock_guard lock(mutex_);
  return failure_;
}

void ChannelGuard::take_keys() {
  net::TrafficKeys keys = handshake_->keys();
  handshake_->wipe();
  seal_fast_ = std::make_unique<net::DatagramSealer>(net::datagram_key(keys.send, uint64_t(GuardedChannel::Fast)));
  seal_reliable_ = std::make_unique<net::DatagramSealer>(net::datagram_key(keys.send, uint64_t(GuardedChannel::Reliable)));
  open_fast_ = std::make_unique<net::DatagramOpener>(net::datagram_key(keys.receive, uint64_t(GuardedChannel::Fast)),
                                                     net::DatagramOpener::Order::Window, max_message_);
  open_reliable_ = std::make_unique<net::DatagramOpener>(net::datagram_key(keys.receive, uint64_t(GuardedChannel::Reliable)),
                                                         net::DatagramOpener::Order::Strict, max_message_);
  sodium_memzero(keys.send.data(), keys.send.size());
  sodium_memzero(keys.receive.data(), keys.receive.size());
}

// Called with the mutex held.
ChannelGuard::Received ChannelGuard::handshake_frame(uint8_t step, std::span<const uint8_t> payload) {
  Received out;
  out.kind = Received::Kind::Handshake;
  auto refuse = [&](const std::string& why) {
    if (failure_.empty()) failure_ = why;
    Received refused;
    refused.reason = why;
    return refused;
  };
  if (!failure_.empty()) return refuse("a handshake frame after the handshake failed");
  if (seal_fast_) return refuse("a handshake frame after the handshake completed");
  if (step == kGuardStepHello) {
    if (payload.size() != net::kHelloSize) return refuse("a hello of " + std::to_string(payload.size()) + " bytes");
    // The connector's hello sent again, before it saw our answer: the answer again, the same
    // bytes. A relay may have dropped it (Janus relays nothing to a subscriber whose channel is not
    // up yet), and a repeat makes no new state. The connector takes a repeat of that answer as
    // already taken.
    if (hello_seen_ && std::equal(payload.begin(), payload.end(), peer_hello_.begin())) {
      if (role_ == net::Role::Listener) out.reply = guard_frame(kGuardStepHello, handshake_->hello());
      return out;
    }
    if (hello_seen_) return refuse("a second hello");
    if (auto bad = net::Handshake::check_hello_prefix(payload.first(net::kHelloPrefixSize), role_)) return refuse(*bad);
    if (role_ == net::Role::Connector && !started_) return refuse("the listener's hello before ours");
    if (role_ == net::Role::Listener) {
      const net::HelloVerdict verdict = gate_.check(payload);
      if (verdict != net::HelloVerdict::Accepted)
        return refuse(verdict == net::HelloVerdict::Replayed
                          ? "a replayed hello"
                          : "the other site's hello does not prove the site key: the two sites hold different keys");
    }
    hello_seen_ = true;
    std::copy(payload.begin(), payload.end(), peer_hello_.begin());
    if (auto bad = handshake_->receive_hello(payload)) return refuse(*bad);
    out.reply = role_ == net::Role::Listener ? guard_frame(kGuardStepHello, handshake_->hello())
                                             : guard_frame(kGuardStepProof, handshake_->proof());
    return out;
  }
  if (step == kGuardStepProof) {
    if (payload.size() != net::kProofSize) return refuse("a proof of " + std::to_string(payload.size()) + " bytes");
    if (!hello_seen_) return refuse("a proof before the hello");
    if (auto bad = handshake_->verify_proof(payload)) {
      // The listener still answers, with bytes that prove nothing, so that both sides fail alike.
      if (role_ == net::Role::Listener) out.reply = guard_frame(kGuardStepProof, net::Handshake::decoy_proof());
      failure_ = "the other site does not hold this site's key (" + *bad + ")";
      out.kind = Received::Kind::Refused;
      out.reason = failure_;
      return out;
    }
    if (role_ == net::Role::Listener) out.reply = guard_frame(kGuardStepProof, handshake_->proof());
    take_keys();
    return out;
  }
  return refuse("a handshake frame of unknown step " + std::to_string(step));
}

ChannelGuard::Received ChannelGuard::receive(GuardedChannel channel, std::span<const uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  Received out;
  if (bytes.size() >= sizeof(kGuardHandshakeMagic) + 1 &&
      std::memcmp(bytes.data(), kGuardHandshakeMagic, sizeof(kGuardHandshakeMagic)) == 0) {
    if (channel != GuardedChannel::Reliable) {
      out.reason = "a handshake frame on rt-fast";
      return out;
    }
    return handshake_frame(bytes[4], bytes.subspan(5));
  }
  if (!seal_fast_) {
    out.kind = Received::Kind::Early;
    out.reason = std::string("a message on ") + guard_channel_name(channel) + " before the handshake completed";
    return out;
  }
  net::DatagramOpener& opener = channel == GuardedChannel::Fast ? *open_fast_ : *open_reliable_;
  std::string why;
  const net::DatagramVerdict verdict = opener.open(bytes, &out.message, &why);
  if (verdict != net::DatagramVerdict::Opened) {
    out.reason = std::string("a record on ") + guard_channel_name(channel) + " refused (" +
                 net::datagram_verdict_name(verdict) + "): " + why;
    return out;
  }
  out.kind = Received::Kind::Message;
  return out;
}

std::optional<std::vector<uint8_t>> ChannelGuard::seal(GuardedChannel channel, std::span<const uint8_t> message) {
  std::lock_guard lock(mutex_);
  if (!seal_fast_) return std::nullopt;
  return (channel == GuardedChannel::Fast ? *seal_fast_ : *seal_reliable_).seal(message);
}

}  // namespace rt::media
