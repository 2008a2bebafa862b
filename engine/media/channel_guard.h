#pragma once
// The site key on the WebRTC data channels: what they carry is sealed end to end, so that a relay
// between the sites (Janus, a TURN server) can neither read nor forge an eye, a skeleton or a
// touch. DTLS protects each hop only.
//
// The keys come from secure_channel.h's Handshake run over the reliable channel itself, not from
// the direct session's: the call may be set up without a session (through Janus), and the
// handshake's ephemeral keys give the data channels forward secrecy of their own. The WebRTC
// offerer is the connector. Handshake frames, in the clear like the session's:
//   "RTDH" | step u8 | payload     step 1: a hello (kHelloSize), step 2: a proof (kProofSize)
//   connector -> hello; listener -> hello; connector -> proof; listener -> proof (or a decoy).
// Then every data-channel message is a sealed record of net/datagram_seal.h: the reliable channel
// opened in strict order, the fast one (unordered, lossy) through the replay window. A CPU module;
// thread-safe (GStreamer calls it from its threads, the sender from its own).
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "net/datagram_seal.h"
#include "net/secure_channel.h"

namespace rt::media {

enum class GuardedChannel { Fast = 0, Reliable = 1 };

class ChannelGuard {
 public:
  ChannelGuard(const net::SessionKey& key, net::Role role, size_t max_message);
  ~ChannelGuard();

  // The connector's hello, to send on the reliable channel once it is open, and again every
  // quarter second until the listener's hello arrives (empty in between, and always for the
  // listener, which answers; the listener ignores a repeat of the hello it answered).
  std::vector<uint8_t> start();

  struct Received {
    // Early: a record before this side's handshake completed, dropped: the other side has its keys
    // first and its first records on the fast channel may overtake the handshake's last frame on
    // the reliable one. Not a refusal: a start under load brings a few.
    enum class Kind { Message, Handshake, Early, Refused } kind = Kind::Refused;
    std::vector<uint8_t> message;  // Message: the opened bytes
    std::vector<uint8_t> reply;    // Handshake: a frame to send back on the reliable channel (may be empty)
    std::string reason;            // Refused: why
  };
  Received receive(GuardedChannel channel, std::span<const uint8_t> bytes);

  // None until the handshake completed: nothing goes out unsealed.
  std::optional<std::vector<uint8_t>> seal(GuardedChannel channel, std::span<const uint8_t> message);

  // The other site left the call and the next one to say hello (the same site restarted, or
  // its replacement) starts a handshake from the beginning: this side forgets the last call's
  // handshake, keys, sequence numbers and replay windows, and a failure of the last one.
  void reset();
  uint64_t resets() const;

  bool ready() const;
  // Why the handshake failed (the other site holds another key, ...); empty if it has not.
  std::string failure() const;

 private:
  Received handshake_frame(uint8_t step, std::span<const uint8_t> payload);
  void take_keys();

  net::SessionKey key_;  // for the handshake after a reset
  net::Role role_;
  size_t max_message_;
  uint64_t resets_ = 0;
  mutable std::mutex mutex_;
  net::HelloGate gate_;
  std::unique_ptr<net::Handshake> handshake_;
  bool started_ = false, hello_seen_ = false;
  std::chrono::steady_clock::time_point last_start_{};
  std::array<uint8_t, net::kHelloSize> peer_hello_{};
  std::string failure_;
  std::unique_ptr<net::DatagramSealer> seal_fast_, seal_reliable_;
  std::unique_ptr<net::DatagramOpener> open_fast_, open_reliable_;
};

}  // namespace rt::media
