#include "net/transport.h"

#include <thread>

namespace rt::net {

const char* connection_state_name(ConnectionState state) {
  switch (state) {
    case ConnectionState::Idle: return "idle";
    case ConnectionState::Connecting: return "connecting";
    case ConnectionState::Connected: return "connected";
    case ConnectionState::Lost: return "lost";
    case ConnectionState::Refused: return "refused";
    case ConnectionState::Ended: return "ended";
  }
  return "unknown";
}

bool Transport::wait_connected(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!status().connected()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

}  // namespace rt::net
