#pragma once
// A site's link over WebRTC (`site --transport webrtc`): the portraits as video and the small
// messages on the data channels of media::WebRtcPeer, set up through the direct session
// (net/session.h). The session still authenticates the two sites (listener and connector as with
// the direct transport) and carries the call's offer, answer and ICE candidates as Signal
// messages, and its goodbye ends the call; nothing else goes over it. The data channels are
// sealed with the site key (media/channel_guard.h): the WebRTC offerer is the session's connector.
//
// Connected means: the session is up, ICE connected, both data channels open and their handshake
// done. Touch events sent before that wait (a few, in order) and go as soon as it is; eye and
// skeletons, which the next copy replaces, are dropped until then; portraits before then are
// dropped by webrtcbin. A heartbeat goes on the reliable channel every heartbeat period. Voice
// frames go as the call's audio track and come out as the VoiceMessages the session would give.
#include <atomic>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "media/pending_touches.h"
#include "media/webrtc_peer.h"
#include "net/transport.h"
#include "net/session.h"

namespace rt::media {

class WebRtcLink : public net::Transport {
 public:
  // `peer`'s offerer flag and guard are set here from the session's role and key. Throws
  // std::runtime_error naming a missing GStreamer element and its package.
  WebRtcLink(net::SessionOptions session, WebRtcPeerOptions peer);
  ~WebRtcLink() override;

  void start() override;
  void stop() override;
  uint16_t local_port() const override;
  void send(const net::Message& message) override;
  void set_handler(std::function<void(const net::Message&)> handler) override;
  net::ConnectionStatus status() const override;
  net::NetCounters counters() const override;
  nlohmann::json transport_json() const override;

 private:
  void on_session_message(const net::Message& message);
  void pump();
  void flush_touches();

  net::SessionOptions session_options_;
  uint32_t width_ = 0, height_ = 0;
  double simulated_loss_ = -1;
  std::shared_ptr<ChannelGuard> guard_;
  std::unique_ptr<WebRtcPeer> peer_;
  std::unique_ptr<net::Session> session_;
  std::function<void(const net::Message&)> handler_;
  std::thread pump_thread_;
  std::atomic<bool> stopping_{false}, started_{false};
  std::chrono::steady_clock::time_point first_connected_{};

  PendingTouches touches_;
  mutable std::mutex mutex_;
  std::string signal_error_;  // a description the peer refused: the call cannot be made
  net::NetCounters counts_;   // messages in and out, and refusals, of the call (the session's added in counters())
  uint64_t heartbeat_sequence_ = 0;
  // The other site's clock, as its last heartbeat read it: the voice's RTP time gets its high bits
  // from it (media/voice_rtp_time.h). Voice waits in the peer until the first heartbeat has come.
  std::optional<uint64_t> peer_clock_us_;
  uint64_t voice_refused_ = 0;  // packets that are no voice frame
  int voice_jitter_buffer_ms_ = 0;
  bool ever_connected_ = false;
  uint64_t connected_us_ = 0;
};

}  // namespace rt::media
