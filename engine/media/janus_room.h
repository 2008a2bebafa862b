#pragma once
// A site's rendezvous in a Janus VideoRoom (`site --janus ws://HOST:PORT --room ID`): Janus's JSON
// API over a WebSocket (media/janus_socket.h), so that two sites behind routers that accept nothing meet at
// a server both can reach. Janus is the signalling server and the SFU: each site publishes its
// tracks and data channel to the room on one peer connection and subscribes to the other site's
// on a second one. A CPU module; its own thread reads the socket, the caller's thread waits for
// answers.
//
//   new JanusRoom  connect, make a session, create the room if it is missing, attach two handles
//   join           this site in the room as a publisher (Janus refuses a third: the room holds two)
//   publish        the publisher peer's offer in, Janus's answer out
//   wait_for_other the other site's publisher id, when it has published
//   subscribe      Janus's offer for the subscriber peer out; start: its answer in
//   trickle        each peer's ICE candidates to Janus (Janus puts its own in its descriptions)
//
// Every message from Janus is checked before use: one that is not JSON, too large, or lacks what
// its kind must carry is refused with a reason (last_error) and counted, never trusted.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "media/janus_socket.h"

namespace rt::media {

struct JanusRoomOptions {
  std::string url;        // ws://HOST:PORT or wss://HOST:PORT
  std::string ca_file;    // wss://: the authorities its certificate is checked against; empty: the system's
  uint64_t room = 0;      // the VideoRoom's number, 1 and up
  std::string pin;        // the room's pin (--room-secret FILE): a room made here gets it
  std::string display;    // this site's name in the room
  std::chrono::milliseconds timeout{10000};  // for each answer
  std::chrono::milliseconds keepalive{25000};  // Janus ends a session silent for a minute
  size_t max_message_bytes = 256 * 1024;       // descriptions are a few kB
};

class JanusRoom {
 public:
  enum class Peer { Publisher, Subscriber };

  // Throws std::runtime_error saying which step failed and what Janus or the network said.
  explicit JanusRoom(JanusRoomOptions options);
  ~JanusRoom();
  JanusRoom(const JanusRoom&) = delete;
  JanusRoom& operator=(const JanusRoom&) = delete;

  // Each throws std::runtime_error with Janus's reason (a wrong pin, a full room, a refused SDP).
  uint64_t join();
  std::string publish(const std::string& offer_sdp);
  std::optional<uint64_t> wait_for_other(std::chrono::milliseconds timeout);
  std::string subscribe(uint64_t feed);
  void start(const std::string& answer_sdp);
  // After the other site left: a new subscriber handle for the next subscription (the old one is
  // detached, which ends its peer connection at Janus). Call it while no subscriber peer exists:
  // trickle() reads the handle.
  void renew_subscriber_handle();
  // From GStreamer's threads: sent in order by the socket's thread. An empty candidate says the
  // gathering is complete.
  void trickle(Peer peer, unsigned mline, const std::string& candidate);

  // The other site's publisher left the room or stopped publishing since it was subscribed to.
  bool other_left() const;
  // The WebSocket to Janus closed, or Janus ended the session: nothing more can be asked of this
  // room object, and why.
  bool closed() const;
  std::string closed_reason() const;
  // A Janus event that ended a peer connection ("hangup: ...") or a refused message; empty if none.
  std::string last_error() const;
  uint64_t messages_refused() const;

 private:
  nlohmann::json request(nlohmann::json message, const char* what);
  nlohmann::json plugin_request(Peer peer, nlohmann::json body, const nlohmann::json* jsep, const char* what);
  void on_message(const std::string& text);
  void on_event(const nlohmann::json& message);  // with mutex_ held
  void on_closed(const std::string& why);
  void refuse(const std::string& why);
  uint64_t handle_of(Peer peer) const { return peer == Peer::Publisher ? publisher_handle_.load() : subscriber_handle_.load(); }
  uint64_t attach(const char* what);

  JanusRoomOptions options_;
  std::unique_ptr<JanusSocket> socket_;
  uint64_t session_ = 0, my_id_ = 0, subscribed_feed_ = 0;
  std::atomic<uint64_t> publisher_handle_{0}, subscriber_handle_{0};

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  uint64_t next_transaction_ = 1;
  std::map<std::string, std::optional<nlohmann::json>> waiting_;  // transaction -> its answer, once come
  std::set<uint64_t> others_;  // publishers in the room other than this site
  bool other_left_ = false, closed_ = false;
  std::string last_error_, closed_reason_;
  std::string create_refused_;  // why Janus would not make the room (it may exist all the same)
  uint64_t refused_ = 0;
  std::thread keepalive_thread_;
  bool stopping_ = false;
};

}  // namespace rt::media
