#pragma once
// One end of the two-site link: an Asio io_context in its own thread, one side listening and the
// other connecting (HOST:PORT), the handshake and sealed records of secure_channel.h, the
// messages of message_codec.h.
//
// Sending never blocks on the network. Eye, skeleton and portrait are newest-wins streams: a newer
// message replaces an older unsent one (counted as stale); one handed to a connection that then
// dies is lost. Voice frames queue in order, boundedly, and are not sent again. Touch events are numbered and acknowledged (in the heartbeats): one stays queued
// until the peer has acknowledged it, and goes again on the next connection, so a touch written
// into a connection that died on the way still arrives; the receiver drops the copies. Received
// messages land in mailboxes the receiver polls (newest wins; touch events queue), and optionally
// in a handler called on the network thread. stop() says goodbye (a last heartbeat marked
// `ending`), so that the peer tells the session's end from a lost connection.
//
// A dropped connection (socket error, no authenticated record for `lost_after`, a record that breaks the stream)
// is retried with exponential backoff by the connecting side; the listener keeps accepting, and
// a newly authenticated connection replaces the old one. status() says whether the remote side
// is there, so the display can keep running and show "remote lost".
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "net/transport.h"
#include "net/message_codec.h"
#include "net/messages.h"
#include "net/net_counters.h"
#include "net/secure_channel.h"

namespace rt::net {

struct SessionOptions {
  Role role = Role::Listener;
  std::string host = "127.0.0.1";  // listener: address to bind ("0.0.0.0" for all); connector: the peer
  uint16_t port = 0;               // listener: 0 picks a free port (local_port() says which)
  SessionKey key;
  EncodeOptions encode;
  DecodeOptions decode;  // e.g. the display's size: a portrait of another size is not decoded
  std::chrono::milliseconds heartbeat_period{200};
  std::chrono::milliseconds lost_after{1000};        // no authenticated record for this long: connection lost
  std::chrono::milliseconds handshake_timeout{2000};
  std::chrono::milliseconds reconnect_min{50}, reconnect_max{2000};
  size_t incoming_touch_capacity = 1024;  // beyond this, unpolled touch events are dropped (counted)
  // Voice frames waiting to be written: half a second of 20 ms frames; beyond it the oldest is
  // dropped (counted as stale). Received ones go to the handler only.
  size_t outgoing_voice_capacity = 25;
  std::string name = "net";               // log prefix, e.g. "site A"
  std::function<void(const std::string&)> log;  // one line per event; default: stderr
};

// "HOST:PORT" ("[::1]:7000" for IPv6). Throws std::invalid_argument saying what is wrong.
std::pair<std::string, uint16_t> parse_host_port(const std::string& text);

class Session : public Transport {
 public:
  explicit Session(SessionOptions options);
  ~Session() override;  // stops
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Binds (listener; throws if it cannot) or starts connecting, and starts the network thread.
  // A session starts once; after stop(), make a new one.
  void start() override;
  void stop() override;
  uint16_t local_port() const override;

  // Thread-safe. Encodes on the calling thread (a portrait's JPEG too); throws
  // std::invalid_argument for a message the peer would reject.
  void send(const Message& message) override;
  // Bytes already encoded (the benchmark times encoding apart), sent as they are on `stream`'s
  // queue (a touch event with the number and session it carries): tests use it to play a peer
  // that holds the key but sends malformed messages.
  void send_encoded(MessageType stream, std::vector<uint8_t> bytes);

  std::optional<EyeMessage> take_eye();
  std::optional<PortraitMessage> take_portrait();
  std::optional<SkeletonMessage> take_skeleton();
  std::optional<HeartbeatMessage> take_heartbeat();
  std::vector<TouchEventMessage> take_touch_events();

  // Set before start(). Called for every accepted message, heartbeats too: on the network thread,
  // portraits on the session's portrait-decoding thread (so a 720p decode never delays a touch).
  // Signals reach the handler only (no mailbox).
  void set_handler(std::function<void(const Message&)> handler) override;

  ConnectionStatus status() const override;
  NetCounters counters() const override;
  nlohmann::json transport_json() const override { return {{"kind", "direct"}}; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rt::net
