#pragma once
// Sealed records for a link that keeps message boundaries but may lose, repeat and reorder
// messages: the WebRTC data channels, whose bytes a relay (Janus, TURN) forwards. One message per
// record, no fragments (a data-channel message is small and arrives whole or not at all):
//   magic "RTDS" | counter u64 | XChaCha20-Poly1305(message), the 12-byte header as associated
//   data, nonce = the counter.
// Keys come from the traffic keys of secure_channel.h's Handshake, one per channel and direction
// (crypto_kdf), so that a record of one channel never opens on the other.
//
// The opener takes one of two orders. Strict, for the ordered, reliable channel: each counter is
// the one after the last, since a gap means a record was deleted on the way (a touch removed)
// and a repeat that one was replayed. Window, for the unordered channel that loses on purpose:
// a counter may skip ahead (lost records) or come late, but only once and within the last
// kReplayWindow counters, as WireGuard's and IPsec's anti-replay windows do; the window moves
// only for records that authenticated, so a forger cannot push it ahead.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "net/secure_channel.h"

namespace rt::net {

inline constexpr uint8_t kDatagramMagic[4] = {'R', 'T', 'D', 'S'};
inline constexpr size_t kDatagramHeaderSize = 12;
inline constexpr size_t kDatagramOverhead = kDatagramHeaderSize + kRecordTagSize;
inline constexpr uint64_t kReplayWindow = 1024;  // counters behind the newest that may still come

// Whether bytes start like a sealed record (the channel may carry other frames beside them).
bool is_sealed_datagram(std::span<const uint8_t> bytes);

// The key of one channel in one direction: crypto_kdf over a traffic key; `channel` names the
// channel (0, 1, ...), and both ends must use the same number for it.
std::array<uint8_t, kTrafficKeySize> datagram_key(const std::array<uint8_t, kTrafficKeySize>& traffic_key, uint64_t channel);

class DatagramSealer {
 public:
  explicit DatagramSealer(const std::array<uint8_t, kTrafficKeySize>& key) : key_(key) {}
  ~DatagramSealer();  // wipes the key
  DatagramSealer(const DatagramSealer&) = delete;
  DatagramSealer& operator=(const DatagramSealer&) = delete;
  std::vector<uint8_t> seal(std::span<const uint8_t> message);
  uint64_t next_counter() const { return counter_; }

 private:
  std::array<uint8_t, kTrafficKeySize> key_;
  uint64_t counter_ = 1;
};

// Malformed: not a record (too short, too long, wrong magic, counter 0). Forged: does not
// authenticate (wrong key, altered bytes, another channel's record). Replayed: authentic in form,
// but its counter was opened already. TooOld: behind the window. OutOfSequence (strict order
// only): not the counter after the last.
enum class DatagramVerdict { Opened, Malformed, Forged, Replayed, TooOld, OutOfSequence };
const char* datagram_verdict_name(DatagramVerdict verdict);

class DatagramOpener {
 public:
  enum class Order { Strict, Window };
  DatagramOpener(const std::array<uint8_t, kTrafficKeySize>& key, Order order, size_t max_message);
  ~DatagramOpener();  // wipes the key
  DatagramOpener(const DatagramOpener&) = delete;
  DatagramOpener& operator=(const DatagramOpener&) = delete;
  // On Opened the message is in *message; otherwise *reason says why, and nothing changed.
  DatagramVerdict open(std::span<const uint8_t> record, std::vector<uint8_t>* message, std::string* reason);
  uint64_t newest_counter() const { return newest_; }

 private:
  bool seen(uint64_t counter) const;
  void mark(uint64_t counter);

  std::array<uint8_t, kTrafficKeySize> key_;
  Order order_;
  size_t max_message_;
  uint64_t newest_ = 0;
  std::array<uint64_t, kReplayWindow / 64> window_{};  // bit c % kReplayWindow: counter c opened
};

}  // namespace rt::net
