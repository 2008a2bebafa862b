#pragma once
// What a site sends and receives through, whichever transport carries it: the direct session
// (net/session.h) or the WebRTC call (media/webrtc_link.h). The sender, the receiver and the run
// of a site hold a Transport and do not know which.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <nlohmann/json.hpp>

#include "net/messages.h"
#include "net/net_counters.h"

namespace rt::net {

// Ended: the peer said goodbye and closed, so the session is over (a connector does not try
// again); Lost: the link failed without a goodbye.
enum class ConnectionState { Idle, Connecting, Connected, Lost, Refused, Ended };
const char* connection_state_name(ConnectionState state);

struct ConnectionStatus {
  ConnectionState state = ConnectionState::Idle;
  uint64_t since_us = 0;  // monotonic clock: when this state began
  std::string reason;     // why lost or refused
  std::string peer;       // address of the current or last peer
  bool connected() const { return state == ConnectionState::Connected; }
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Binds or starts connecting; once.
  virtual void start() = 0;
  virtual void stop() = 0;
  // The listener's port (0 before start or for a connector).
  virtual uint16_t local_port() const = 0;
  // Thread-safe; never blocks on the network. Throws std::invalid_argument for a message the
  // peer would refuse.
  virtual void send(const Message& message) = 0;
  // Set before start(): every accepted message, from the link's threads.
  virtual void set_handler(std::function<void(const Message&)> handler) = 0;
  virtual ConnectionStatus status() const = 0;
  virtual NetCounters counters() const = 0;
  // Polls status() until connected or the timeout passes.
  bool wait_connected(std::chrono::milliseconds timeout) const;
  // What the transport itself measured, for metrics.json ("transport": {...}).
  virtual nlohmann::json transport_json() const = 0;
};

}  // namespace rt::net
