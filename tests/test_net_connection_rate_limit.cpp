// The per-network token bucket a listener sheds floods with: the burst, the refill, networks
// apart, a clock that goes back, the bound on how many it remembers, what a network is.
#include <catch2/catch.hpp>

#include "net/connection_rate_limit.h"

using rt::net::address_key;
using rt::net::ConnectionRateLimit;
using rt::net::prefix_key;

namespace {
int admitted(ConnectionRateLimit& limit, const std::string& address, int tries, uint64_t now_us) {
  int n = 0;
  for (int i = 0; i < tries; ++i) n += limit.admit(address, now_us);
  return n;
}
}  // namespace

TEST_CASE("an address gets its burst at once, then its rate") {
  ConnectionRateLimit limit(10, 20, 16);
  CHECK(admitted(limit, "10.0.0.1", 100, 1'000'000) == 20);
  CHECK(admitted(limit, "10.0.0.1", 100, 1'050'000) == 0);   // half a token
  CHECK(admitted(limit, "10.0.0.1", 100, 1'100'000) == 1);   // one token in 100 ms
  CHECK(admitted(limit, "10.0.0.1", 100, 2'100'000) == 10);  // a second: ten
  CHECK(admitted(limit, "10.0.0.1", 100, 60'000'000) == 20);  // never more than the burst
}

TEST_CASE("one address over its rate leaves the others alone") {
  ConnectionRateLimit limit(10, 20, 16);
  CHECK(admitted(limit, "10.0.0.1", 1000, 5'000'000) == 20);
  CHECK(limit.admit("10.0.0.2", 5'000'000));
  CHECK(limit.admit("::1", 5'000'000));
  CHECK_FALSE(limit.admit("10.0.0.1", 5'000'000));
}

TEST_CASE("a clock that goes back refills nothing and breaks nothing") {
  ConnectionRateLimit limit(10, 2, 16);
  CHECK(admitted(limit, "a", 5, 10'000'000) == 2);
  CHECK(admitted(limit, "a", 5, 1'000'000) == 0);
  CHECK(admitted(limit, "a", 5, 10'100'000) == 1);  // the refill counts from the latest time seen
  CHECK(admitted(limit, "a", 5, 0) == 0);
}

TEST_CASE("the addresses remembered stay bounded, and a forgotten one starts afresh") {
  ConnectionRateLimit limit(1, 3, 8);
  // Many addresses, each over its rate at once: the table never grows past its bound.
  for (int i = 0; i < 1000; ++i) {
    const std::string address = "10.1." + std::to_string(i / 256) + "." + std::to_string(i % 256);
    CHECK(admitted(limit, address, 5, 1'000'000 + uint64_t(i)) == 3);
    REQUIRE(limit.addresses_tracked() <= 8);
  }
  // The newest ones are still remembered as spent; the table has no room for old ones, so the
  // first address, long forgotten, gets a full burst again.
  CHECK_FALSE(limit.admit("10.1.3.231", 1'001'000));
  CHECK(admitted(limit, "10.1.0.0", 5, 1'001'000) == 3);
}

TEST_CASE("to make room, addresses whose bucket is full again go before one still over its rate") {
  ConnectionRateLimit limit(1, 3, 8);
  for (int i = 0; i < 7; ++i) CHECK(limit.admit("idle" + std::to_string(i), 100'000'000));
  CHECK(admitted(limit, "busy", 10, 110'000'000) == 3);
  REQUIRE(limit.addresses_tracked() == 8);
  // The idle ones were seen before the busy one, but have their burst back: they go, it stays.
  for (int i = 0; i < 6; ++i) CHECK(limit.admit("new" + std::to_string(i), 110'000'000));
  CHECK(limit.addresses_tracked() == 7);
  CHECK_FALSE(limit.admit("busy", 110'000'000));
}

TEST_CASE("a rate limit that would admit nothing is refused") {
  CHECK_THROWS_WITH(ConnectionRateLimit(0, 20, 16), Catch::Contains("rate must be positive"));
  CHECK_THROWS(ConnectionRateLimit(10, 0, 16));
  CHECK_THROWS(ConnectionRateLimit(10, 20, 0));
}

TEST_CASE("networks, not addresses: an IPv4 /24 and an IPv6 /64 share one bucket") {
  auto prefix = [](const char* text) { return prefix_key(address_key(asio::ip::make_address(text))); };
  CHECK(prefix("192.0.2.1") == prefix("192.0.2.254"));
  CHECK(prefix("192.0.2.1") != prefix("192.0.3.1"));
  CHECK(prefix("2001:db8:1:2::1") == prefix("2001:db8:1:2:ffff:ffff:ffff:ffff"));
  CHECK(prefix("2001:db8:1:2::1") != prefix("2001:db8:1:3::1"));
  CHECK(prefix("::ffff:192.0.2.7") == prefix("192.0.2.1"));  // IPv4 mapped into IPv6
  CHECK(address_key(asio::ip::make_address("::ffff:192.0.2.7")) == address_key(asio::ip::make_address("192.0.2.7")));
  // A stranger with a whole /64 (an address per connection) has one rate, not 2^64 of them.
  ConnectionRateLimit limit(10, 20, 1024);
  int admitted = 0;
  for (int i = 0; i < 100; ++i) {
    const std::string address = "2001:db8:1:2::" + std::to_string(i + 1);
    admitted += limit.admit(prefix(address.c_str()), 0);
  }
  CHECK(admitted == 20);
  CHECK(limit.addresses_tracked() == 1);
}
