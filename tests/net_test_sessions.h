#pragma once
// Two sessions on loopback for the network tests: a listener on a free port and a connector to it
// (directly or through a fault proxy), short timeouts so faults show within a test's seconds, and
// log lines collected instead of printed.
#include <arpa/inet.h>
#include <netinet/in.h>

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "net/fault_proxy.h"
#include "net/session.h"

namespace rt::test {

struct LogLines {
  std::mutex mutex;
  std::vector<std::string> lines;
  std::function<void(const std::string&)> sink() {
    return [this](const std::string& line) {
      std::lock_guard lock(mutex);
      lines.push_back(line);
    };
  }
  bool contains(const std::string& text) {
    std::lock_guard lock(mutex);
    for (const auto& line : lines)
      if (line.find(text) != std::string::npos) return true;
    return false;
  }
};

inline net::SessionOptions test_session_options(net::Role role, const net::SessionKey& key, LogLines& log,
                                                const std::string& name) {
  net::SessionOptions o;
  o.role = role;
  o.key = key;
  o.name = name;
  o.heartbeat_period = std::chrono::milliseconds(50);
  o.lost_after = std::chrono::milliseconds(1500);  // long enough for a loaded CI machine
  o.handshake_timeout = std::chrono::milliseconds(1000);
  o.reconnect_min = std::chrono::milliseconds(20);
  o.reconnect_max = std::chrono::milliseconds(200);
  o.log = log.sink();
  return o;
}

// Polls `done` every 2 ms until it holds or `timeout` passes.
// 127.0.0.1:port, for tests that open raw sockets against a session.
inline sockaddr_in loopback_address(uint16_t port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return address;
}

inline bool eventually(const std::function<bool()>& done, std::chrono::milliseconds timeout = std::chrono::milliseconds(3000)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

}  // namespace rt::test
