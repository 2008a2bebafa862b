#pragma once
// How often each network (see prefix_key) may open a new connection: a token bucket per network.
// A listener closes a connection over its network's rate before reading anything from it, so that
// one stranger's flood costs it an accept and a close while any other network (the real peer's)
// still gets in at once.
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>

#include <asio/ip/address.hpp>

namespace rt::net {

// An IP address by its bytes (printing it costs more than the rest of shedding a connection); an
// IPv4 address mapped into IPv6 is the IPv4 address.
std::string address_key(const asio::ip::address& address);
// The network an address belongs to, as the rate limit counts it: an IPv4 /24 or an IPv6 /64, of
// which one host or one customer of a provider can have many addresses.
std::string prefix_key(const std::string& address_key);

class ConnectionRateLimit {
 public:
  // `per_second` new connections a second, `burst` at once; at most `max_addresses` are
  // remembered (an address forgotten starts again with a full burst).
  ConnectionRateLimit(uint32_t per_second, uint32_t burst, size_t max_addresses);

  // True when `address` may open one more connection at `now_us`, which it then spends.
  bool admit(const std::string& address, uint64_t now_us);

  size_t addresses_tracked() const { return buckets_.size(); }

 private:
  // Tokens are counted in millionths, so that a microsecond's refill is exact: `per_second` of them.
  static constexpr uint64_t kToken = 1'000'000;
  struct Bucket {
    uint64_t tokens;
    uint64_t last_us;
  };
  uint64_t refilled(const Bucket& bucket, uint64_t now_us) const;
  void make_room(uint64_t now_us);

  uint64_t per_second_, burst_;
  size_t max_addresses_;
  std::unordered_map<std::string, Bucket> buckets_;
};

}  // namespace rt::net
