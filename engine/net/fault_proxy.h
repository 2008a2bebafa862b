#pragma once
// A loopback TCP proxy that injects faults between the two sessions, for the tests and the demo's
// fault options: the connector connects to the proxy, the proxy to the listener. It understands
// only the framing (the two handshake messages, then record headers), never the contents, so it
// can delay and jitter whole records, lose one the way a lossy network hurts a TCP stream (the
// connection dies there: TCP never delivers a stream with a hole in it), cut the connection,
// inject garbage bytes, or delete one record as an attacker in the path would. Costs nothing
// when not used: sessions talk directly when no proxy is set up.
#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace rt::net {

struct FaultOptions {
  std::chrono::microseconds delay{0};   // every record and handshake message, each direction
  std::chrono::microseconds jitter{0};  // plus uniform 0..jitter per record; order is kept (TCP)
  // Probability that a record is lost (never the handshake): the link is cut where it was lost,
  // both directions, as a TCP connection that could not get it through dies; the connector then
  // reconnects. Records before it still arrive.
  double loss = 0.0;
  // A bottleneck, each direction: a record (or handshake message) leaves its bytes' time at this
  // rate after the one before it. 0: as fast as loopback goes.
  double bytes_per_second = 0.0;
  std::optional<std::chrono::milliseconds> disconnect_after;  // cut the connections once, this long after start()
  std::optional<std::chrono::milliseconds> garbage_after;     // inject garbage once, this long after start()
  size_t garbage_bytes = 64;
  uint32_t seed = 1;  // loss, jitter and garbage are reproducible
};

struct FaultCounts {
  uint64_t connections = 0;
  uint64_t records_forwarded = 0;
  uint64_t records_dropped = 0;  // lost, each cutting its link
  uint64_t records_deleted = 0;  // by delete_next_record
  uint64_t lengths_rewritten = 0;  // by rewrite_next_record_length
  uint64_t garbage_injections = 0, garbage_bytes = 0;
  uint64_t disconnects = 0;
  uint64_t bytes_swallowed = 0;  // by the blackhole
  nlohmann::json to_json() const;
};

class FaultProxy {
 public:
  FaultProxy(std::string target_host, uint16_t target_port, FaultOptions options);
  ~FaultProxy();
  FaultProxy(const FaultProxy&) = delete;
  FaultProxy& operator=(const FaultProxy&) = delete;

  void start();  // listens on 127.0.0.1, a free port
  void stop();
  uint16_t port() const;

  // Closes every proxied connection now (both sessions see the peer go); new ones are accepted.
  void disconnect_now();
  // Random bytes into the connector-to-listener stream, between two records.
  void inject_garbage_now(size_t bytes);
  // While on, every byte in both directions is swallowed, handshakes too: a link that has gone
  // silent without closing, which only the sessions' heartbeat timeouts can notice. Turned off,
  // it cuts the connections whose bytes it swallowed (TCP cannot skip them).
  void set_blackhole(bool on);
  // Deletes the next connector-to-listener record of this ciphertext length and forwards the
  // rest, as an attacker in the path could (the sizes tell message types apart): the receiver's
  // counters must notice the gap.
  void delete_next_record(uint32_t ciphertext_length);
  // Rewrites the length in the next connector-to-listener record's header (the bytes behind it
  // go on as they were), as an attacker in the path could: the receiver must find the stream out
  // of step, or the link dead, without trusting the length.
  void rewrite_next_record_length(uint32_t new_length);
  FaultCounts counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rt::net
