#pragma once
// A site's link through a Janus VideoRoom (`site --transport webrtc --janus ws://HOST:PORT --room ID
// [--room-secret FILE]`): neither site accepts a connection; both reach Janus, which relays. The
// site publishes its portraits and messages on one relayed WebRtcPeer and receives the other
// site's on a second, subscribed to the other site's publisher (media/janus_room.h). The site key
// still seals everything on the data channels, its handshake relayed like the rest (a
// subscriber's replies go out through its site's publisher), so Janus can neither read nor forge
// a touch, a skeleton, the eye or the voice. The pictures are protected hop by hop only (DTLS-SRTP):
// Janus sees them.
//
// Site A takes the handshake's connector part, site B the listener's. Connected means: both
// peers up and the handshake done. Touch events wait for it (a few, in order) as on the WebRTC
// link; the rest is dropped until then.
//
// When the other site leaves the room (its process ended, its machine restarted), the link stays
// in the room with its publication and waits for the other site to come back: the subscriber
// peer and its Janus handle go, the guard forgets the last call's handshake and keys, and the
// next publisher in the room is subscribed to and handshaken with from the start. Touches made
// while the other site is away are dropped (counted): nobody is there to feel them. When the
// connection to Janus itself closes (Janus restarted), the link makes everything again (a new
// session, join, publish, subscribe, handshake), trying a bounded number of times with back-off
// and saying so in status().
#include <atomic>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <thread>

#include "media/janus_room.h"
#include "media/pending_touches.h"
#include "media/webrtc_peer.h"
#include "net/session.h"
#include "net/transport.h"

namespace rt::media {

class JanusLink : public net::Transport {
 public:
  // `session` gives the key, the handshake's role, the site's name and the heartbeat period;
  // nothing listens or connects but the WebSocket to Janus. Throws std::invalid_argument for a bad
  // Janus URL or room (the room itself is joined by start()'s thread).
  JanusLink(net::SessionOptions session, JanusRoomOptions room, WebRtcPeerOptions peer);
  ~JanusLink() override;

  void start() override;
  void stop() override;
  uint16_t local_port() const override { return 0; }
  void send(const net::Message& message) override;
  void set_handler(std::function<void(const net::Message&)> handler) override;
  net::ConnectionStatus status() const override;
  net::NetCounters counters() const override;
  nlohmann::json transport_json() const override;

 private:
  void run();
  void call();
  void leave_janus(const std::string& why, const std::string& retry_error, int attempt, std::chrono::milliseconds delay);
  void set_up();
  Signalling signalling(JanusRoom::Peer which);
  void subscribe_to(uint64_t other);
  void drop_other_site();
  void pump_signalling();
  void pump_received(bool& busy);
  void flush_touches();
  void flush_touches_to(WebRtcPeer* peer);
  void fail(const std::string& why);

  net::SessionOptions session_;
  JanusRoomOptions room_options_;
  WebRtcPeerOptions peer_options_;
  std::shared_ptr<ChannelGuard> guard_;
  std::function<void(const net::Message&)> handler_;
  std::thread thread_;
  std::atomic<bool> stopping_{false}, started_{false};

  // Made by the link's thread, read by send() and status(): the room and the publisher are set
  // once and kept until the destructor; the subscriber changes with the other site (the link's
  // thread changes it with mutex_ held, others read it with mutex_ held).
  // After a lost connection to Janus all three are made again; publisher_mutex_, held shared by
  // send() while it uses the publisher, lets the link's thread replace it safely.
  std::unique_ptr<JanusRoom> room_;
  std::unique_ptr<WebRtcPeer> publisher_, subscriber_;
  std::atomic<WebRtcPeer*> sending_{nullptr};
  std::shared_mutex publisher_mutex_;
  bool subscribed_in_room_ = false;  // this room object's subscriber handle was used (link's thread)

  mutable std::mutex mutex_;
  struct Said {
    JanusRoom::Peer peer;
    std::string type, sdp;
  };
  std::deque<Said> said_;  // descriptions from GStreamer's threads, for Janus on the link's thread
  PendingTouches touches_;
  std::string failure_;
  std::string failure_seen_;  // a departed subscriber's last refusal
  std::string stage_ = "subscribed";  // while connecting: which part of the call is not up yet
  net::NetCounters counts_;
  uint64_t heartbeat_sequence_ = 0, my_id_ = 0, other_id_ = 0;
  bool ever_connected_ = false, connected_now_ = false;
  bool other_away_ = false;  // the other site left and has not published again yet
  uint64_t connected_us_ = 0;
  // The other site leaving and coming back: how often, when it last left, came back (published
  // again) and was connected again, and the touches dropped while it was away.
  uint64_t other_left_count_ = 0, rejoins_ = 0, left_us_ = 0, came_back_us_ = 0;
  double last_away_s_ = 0, last_reconnect_s_ = 0;
  uint64_t touches_dropped_away_ = 0;
  // The departed subscribers' counts, so that the call's totals survive a rejoin.
  WebRtcCounters retired_, before_rejoin_, retired_sent_;
  // The other site coming back after it left, or both sites after Janus was lost: what the next
  // connection ends.
  enum class ComingBack { No, OtherSite, Janus } coming_back_ = ComingBack::No;
  // The connection to Janus: why it was lost (empty while it is up), how often, how often the
  // site joined the room again, the tries since and the last one's error, the outage's length.
  std::string janus_lost_, janus_retry_error_;
  uint64_t janus_lost_count_ = 0, janus_rejoins_ = 0, janus_lost_us_ = 0, janus_next_try_us_ = 0;
  int janus_attempt_ = 0;
  double last_janus_outage_s_ = 0;
};

}  // namespace rt::media
