// A listener under a flood of strangers from many networks: forged hellos (the right prefix, no
// key behind the MAC) and silent connections, 1,000 new connections a second from 64 loopback
// addresses in 64 different /24 networks, while the real peer connects. The peer must get in
// within a second of trying, no stranger may cost the listener handshake state, and the network
// thread's share of a core is measured and printed.
//
// REMOTETOUCH_FLOOD_SECONDS sets the flood's length (default 4 s: the peer tries halfway, while
// the per-network buckets still let most of the flood in, the harder half of a longer flood).
#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <sodium.h>

#include "net_test_sessions.h"

using namespace rt;
using namespace rt::net;

namespace {

constexpr std::chrono::milliseconds kPatienceNetFlood{20000};

double flood_seconds() {
  const char* text = std::getenv("REMOTETOUCH_FLOOD_SECONDS");
  const double seconds = text ? std::atof(text) : 4.0;
  return seconds > 0.5 && seconds <= 60 ? seconds : 4.0;
}

// CPU seconds a thread of this process has used, found by its name (/proc/self/task/*/comm).
std::optional<double> thread_cpu_seconds(const std::string& name) {
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string line;
    std::getline(comm, line);
    if (line != name) continue;
    std::ifstream stat_file(task.path() / "stat");
    std::string stat((std::istreambuf_iterator<char>(stat_file)), std::istreambuf_iterator<char>());
    // After the name in parentheses: state is field 3; utime and stime are fields 14 and 15.
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));
    std::string field;
    unsigned long long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> field; ++i) {
      if (i == 14) utime = std::stoull(field);
      if (i == 15) stime = std::stoull(field);
    }
    return double(utime + stime) / double(::sysconf(_SC_CLK_TCK));
  }
  return std::nullopt;
}

// A connection to `to` from the loopback address `from`; -1 when it could not be made in time
// (the listener's backlog full: a flood that outruns it, counted, not a failure of the test).
int connect_from(const sockaddr_in& to, const std::string& from) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  timeval timeout{0, 200'000};
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
  sockaddr_in source{};
  source.sin_family = AF_INET;
  ::inet_pton(AF_INET, from.c_str(), &source.sin_addr);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&source), sizeof source) != 0 ||
      ::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

struct FloodResult {
  uint64_t connections = 0, failed = 0, forged_hellos = 0, silent = 0;
  double seconds = 0;
};

// `rate` new connections a second for `seconds`, round-robin over 64 addresses in 64 /24s. Three
// in four send a forged hello (our version's prefix, random bytes after it: a MAC no one with the
// key made) and close; one in four says nothing and stays open for a second, holding a place
// among the connections awaiting their hello.
FloodResult flood(const sockaddr_in& to, double rate, double seconds, const std::atomic<bool>& stop) {
  FloodResult result;
  const auto prefix = Handshake::hello_prefix(Role::Connector);
  std::deque<std::pair<std::chrono::steady_clock::time_point, int>> silent;
  const auto start = std::chrono::steady_clock::now();
  const auto end = start + std::chrono::duration<double>(seconds);
  for (uint64_t k = 0; !stop; ++k) {
    const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(double(k) / rate));
    if (due >= end) break;
    std::this_thread::sleep_until(due);  // behind schedule: at once
    const auto now = std::chrono::steady_clock::now();
    while (!silent.empty() && now - silent.front().first > std::chrono::seconds(1)) {
      ::close(silent.front().second);
      silent.pop_front();
    }
    const int fd = connect_from(to, "127.1." + std::to_string(k % 64) + ".2");
    ++result.connections;
    if (fd < 0) {
      ++result.failed;
      continue;
    }
    if (k % 4 == 3) {
      silent.emplace_back(now, fd);
      ++result.silent;
      continue;
    }
    std::array<uint8_t, kHelloSize> hello{};
    std::copy(prefix.begin(), prefix.end(), hello.begin());
    randombytes_buf(hello.data() + kHelloPrefixSize, kHelloSize - kHelloPrefixSize);
    if (::send(fd, hello.data(), hello.size(), MSG_NOSIGNAL) == ssize_t(hello.size())) ++result.forged_hellos;
    ::close(fd);
  }
  for (const auto& [when, fd] : silent) ::close(fd);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

TEST_CASE("1,000 strangers a second from 64 networks: the peer gets in within a second, no stranger costs handshake state") {
  ensure_sodium();
  test::LogLines log;
  const SessionKey key = random_session_key();
  // The production timeouts: a silent stranger holds its place as long as it would in a site.
  SessionOptions listener_options = test::test_session_options(Role::Listener, key, log, "B");
  listener_options.handshake_timeout = SessionOptions{}.handshake_timeout;
  listener_options.heartbeat_period = SessionOptions{}.heartbeat_period;
  Session listener(listener_options);
  listener.start();
  const sockaddr_in address = test::loopback_address(listener.local_port());
  REQUIRE(test::eventually([&] { return thread_cpu_seconds("net B").has_value(); }, kPatienceNetFlood));

  const double seconds = flood_seconds();
  const double cpu_before = *thread_cpu_seconds("net B");
  const auto flood_start = std::chrono::steady_clock::now();
  std::atomic<bool> stop{false};
  FloodResult result;
  std::thread flooder([&] { result = flood(address, 1000, seconds, stop); });

  // Halfway, the real peer (another address, another network) tries, as a site does: production
  // back-off.
  std::this_thread::sleep_until(flood_start + std::chrono::duration<double>(seconds / 2));
  SessionOptions options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = listener.local_port();
  options.reconnect_min = SessionOptions{}.reconnect_min;
  options.reconnect_max = SessionOptions{}.reconnect_max;
  Session connector(options);
  const auto tried = std::chrono::steady_clock::now();
  connector.start();
  const bool connected = connector.wait_connected(kPatienceNetFlood);
  const double connect_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tried).count();
  flooder.join();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - flood_start).count();
  const double cpu_s = *thread_cpu_seconds("net B") - cpu_before;

  const NetCounters c = listener.counters();
  std::cout << "flood: " << result.connections << " connections in " << result.seconds << " s ("
            << double(result.connections) / result.seconds << " a second; " << result.failed << " could not connect, "
            << result.forged_hellos << " forged hellos, " << result.silent << " silent) from 64 networks\n"
            << "  the peer connected after " << connect_s * 1000 << " ms\n"
            << "  the listener's network thread: " << cpu_s << " s of CPU in " << wall_s << " s, "
            << 100 * cpu_s / wall_s << " % of a core\n"
            << "  listener " << c.to_json().dump() << "\n";
  CHECK(connected);
  CHECK(connect_s < 1.0);
  // The flood reached the listener at about its rate (a loaded machine may fall behind a little).
  CHECK(double(result.connections) >= 0.7 * 1000 * seconds);
  // Every forged hello the listener read was refused at its MAC, and made no handshake state:
  // the peer's hello made the only one.
  CHECK(c.hellos_not_authentic > 0);
  CHECK(c.handshakes_started == c.handshakes_ok);
  CHECK(c.handshakes_ok == 1);
  CHECK(c.hellos_replayed == 0);
  // The network thread's share of a core, measured while the flood lasts, with the peer's
  // handshake and its heartbeats in it.
  CHECK(cpu_s < 0.3 * wall_s);
  stop = true;
}

TEST_CASE("a stranger flooding from the peer's own address (its host, its NAT) does not keep the peer out") {
  ensure_sodium();
  test::LogLines log;
  const SessionKey key = random_session_key();
  SessionOptions listener_options = test::test_session_options(Role::Listener, key, log, "B");
  listener_options.handshake_timeout = SessionOptions{}.handshake_timeout;
  Session listener(listener_options);
  listener.start();
  SessionOptions options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = listener.local_port();
  options.reconnect_min = SessionOptions{}.reconnect_min;
  options.reconnect_max = SessionOptions{}.reconnect_max;
  {
    // The peer connects once from 127.0.0.1, then its run ends.
    Session first(options);
    first.start();
    REQUIRE(first.wait_connected(kPatienceNetFlood));
  }
  const sockaddr_in address = test::loopback_address(listener.local_port());
  // A stranger on that address (never shed: it is the peer's) floods silent connections and
  // forged hellos, 1,000 a second; the peer's next run tries halfway.
  std::atomic<bool> stop{false};
  FloodResult result;
  const double seconds = std::min(flood_seconds(), 4.0);
  const auto flood_start = std::chrono::steady_clock::now();
  std::thread flooder([&] {
    const auto prefix = Handshake::hello_prefix(Role::Connector);
    std::deque<std::pair<std::chrono::steady_clock::time_point, int>> silent;
    const auto end = flood_start + std::chrono::duration<double>(seconds);
    for (uint64_t k = 0; !stop; ++k) {
      const auto due = flood_start + std::chrono::microseconds(k * 1000);
      if (due >= end) break;
      std::this_thread::sleep_until(due);
      const auto now = std::chrono::steady_clock::now();
      while (!silent.empty() && now - silent.front().first > std::chrono::seconds(1)) {
        ::close(silent.front().second);
        silent.pop_front();
      }
      const int fd = connect_from(address, "127.0.0.1");
      ++result.connections;
      if (fd < 0) {
        ++result.failed;
        continue;
      }
      if (k % 2) {
        silent.emplace_back(now, fd);
        continue;
      }
      std::array<uint8_t, kHelloSize> hello{};
      std::copy(prefix.begin(), prefix.end(), hello.begin());
      randombytes_buf(hello.data() + kHelloPrefixSize, kHelloSize - kHelloPrefixSize);
      (void)::send(fd, hello.data(), hello.size(), MSG_NOSIGNAL);
      ::close(fd);
    }
    for (const auto& [when, fd] : silent) ::close(fd);
  });
  std::this_thread::sleep_until(flood_start + std::chrono::duration<double>(seconds / 2));
  Session again(options);
  const auto tried = std::chrono::steady_clock::now();
  again.start();
  const bool connected = again.wait_connected(kPatienceNetFlood);
  const double connect_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tried).count();
  stop = true;
  flooder.join();
  const NetCounters c = listener.counters();
  std::cout << "a stranger on the peer's address: " << result.connections << " connections (" << result.failed
            << " could not connect); the peer connected after " << connect_s * 1000 << " ms\n  listener " << c.to_json().dump()
            << "\n";
  CHECK(connected);
  CHECK(connect_s < 1.0);
  CHECK(c.handshakes_started == c.handshakes_ok);
  CHECK(c.handshakes_ok == 2);
}
