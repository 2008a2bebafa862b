#include "media/janus_link.h"

#include <stdexcept>

#include "media/pending_touches.h"
#include "net/datagram_seal.h"
#include "time/monotonic_clock.h"

namespace rt::media {
namespace {

constexpr auto kJanusPumpPeriod = std::chrono::milliseconds(2);

}  // namespace

JanusLink::JanusLink(net::SessionOptions session, JanusRoomOptions room, WebRtcPeerOptions peer)
    : session_(std::move(session)), room_options_(std::move(room)), peer_options_(std::move(peer)) {
  parse_janus_url(room_options_.url);
  if (room_options_.room == 0) throw std::invalid_argument("--room: a room number from 1 up");
  if (room_options_.display.empty()) room_options_.display = session_.name;
  guard_ = std::make_shared<ChannelGuard>(session_.key, session_.role, 64 * 1024 - net::kDatagramOverhead);
  peer_options_.relayed = true;
  peer_options_.guard = guard_;
}

JanusLink::~JanusLink() {
  stop();
  // The peers first: their GStreamer threads call into the room's trickle.
  subscriber_.reset();
  publisher_.reset();
  room_.reset();
}

void JanusLink::start() {
  if (started_.exchange(true)) throw std::logic_error("a link starts once");
  thread_ = std::thread([this] { run(); });
}

void JanusLink::stop() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
}

void JanusLink::set_handler(std::function<void(const net::Message&)> handler) { handler_ = std::move(handler); }

void JanusLink::fail(const std::string& why) {
  std::lock_guard lock(mutex_);
  if (failure_.empty()) failure_ = why;
}

void JanusLink::set_up() {
  room_ = std::make_unique<JanusRoom>(room_options_);
  const uint64_t me = room_->join();
  WebRtcPeerOptions publishing = peer_options_;
  publishing.name = session_.name + " publisher";
  publishing.offerer = true;
  auto publisher = std::make_unique<WebRtcPeer>(publishing, signalling(JanusRoom::Peer::Publisher));
  {
    std::lock_guard lock(mutex_);
    my_id_ = me;
    publisher_ = std::move(publisher);
  }
  sending_ = publisher_.get();
  publisher_->send_portrait(blank_portrait(peer_options_.width, peer_options_.height));
}

Signalling JanusLink::signalling(JanusRoom::Peer which) {
  Signalling s;
  s.on_description = [this, which](const std::string& type, const std::string& sdp) {
    std::lock_guard lock(mutex_);
    said_.push_back({which, type, sdp});
  };
  s.on_candidate = [this, which](unsigned mline, const std::string& candidate) { room_->trickle(which, mline, candidate); };
  return s;
}

// The other site's publisher, once it publishes; the subscriber's offer comes from Janus.
void JanusLink::subscribe_to(uint64_t other) {
  bool again = false;
  {
    std::lock_guard lock(mutex_);
    again = other_left_count_ > 0;
  }
  if (again) room_->renew_subscriber_handle();
  WebRtcPeerOptions receiving = peer_options_;
  receiving.name = session_.name + " subscriber";
  receiving.offerer = false;
  receiving.handshake_out = [this](std::span<const uint8_t> frame) { return publisher_->send_handshake(frame); };
  auto subscriber = std::make_unique<WebRtcPeer>(receiving, signalling(JanusRoom::Peer::Subscriber));
  const std::string offer = room_->subscribe(other);
  if (const std::string error = subscriber->set_remote_description("offer", offer); !error.empty())
    throw std::runtime_error("Janus's offer for the other site's streams was refused: " + error);
  std::lock_guard lock(mutex_);
  subscriber_ = std::move(subscriber);
  other_id_ = other;
  other_away_ = false;
  if (again) came_back_us_ = monotonic_now_us(), before_rejoin_ = retired_;
}

namespace {

void add_receiving_counts(WebRtcCounters& into, const WebRtcCounters& from) {
  into.portraits_received += from.portraits_received;
  into.portraits_dropped += from.portraits_dropped;
  into.frames_unpaired += from.frames_unpaired;
  into.portraits_lost += from.portraits_lost;
  into.messages_received += from.messages_received;
  into.messages_refused += from.messages_refused;
  into.messages_early += from.messages_early;
  into.keyframes_asked += from.keyframes_asked;
}

}  // namespace

void JanusLink::drop_other_site() {
  std::unique_ptr<WebRtcPeer> departed;
  {
    std::lock_guard lock(mutex_);
    add_receiving_counts(retired_, subscriber_->counters());
    if (subscriber_->counters().messages_refused) failure_seen_ = subscriber_->last_error();
    departed = std::move(subscriber_);
    // Descriptions the departed subscriber made and Janus has not had yet belong to no call now.
    std::erase_if(said_, [](const Said& s) { return s.peer == JanusRoom::Peer::Subscriber; });
    other_away_ = true;
    connected_now_ = false;
    ++other_left_count_;
    left_us_ = monotonic_now_us();
  }
  const size_t dropped = touches_.drop_all();
  {
    std::lock_guard lock(mutex_);
    touches_dropped_away_ += dropped;
  }
  // The peer first, outside the lock (its GStreamer threads call back into the link while they
  // stop), then the guard: nothing of the departed site's can reach the fresh handshake.
  departed.reset();
  guard_->reset();
}

void JanusLink::pump_signalling() {
  std::deque<Said> now;
  {
    std::lock_guard lock(mutex_);
    now.swap(said_);
  }
  for (const Said& s : now) {
    if (s.peer == JanusRoom::Peer::Publisher && s.type == "offer") {
      const std::string answer = room_->publish(s.sdp);
      if (const std::string error = publisher_->set_remote_description("answer", answer); !error.empty())
        throw std::runtime_error("Janus's answer to this site's offer was refused: " + error);
    } else if (s.peer == JanusRoom::Peer::Subscriber && s.type == "answer") {
      room_->start(s.sdp);
    }
  }
}

void JanusLink::run() {
  try {
    set_up();
    auto next_heartbeat = std::chrono::steady_clock::now();
    while (!stopping_) {
      pump_signalling();
      if (!subscriber_) {
        // Alone in the room (at the start, or since the other site left): this site's publication
        // stays up, and the next publisher in the room is the other site's.
        if (const std::optional<uint64_t> other = room_->wait_for_other(std::chrono::milliseconds(20))) subscribe_to(*other);
        continue;
      }
      bool busy = false;
      pump_received(busy);
      if (room_->other_left()) {
        drop_other_site();
        continue;
      }
      // Both connected() calls also send the guard's hello (through the publisher) until answered.
      const bool publishing = publisher_->connected(), receiving = subscriber_->connected();
      if (!publishing || !receiving) {
        std::lock_guard lock(mutex_);
        stage_ = std::string("this site's publication ") + (publisher_->channels_up() ? "up" : "not up yet") + ", the other's " +
                 (subscriber_->channels_up() ? "up" : "not up yet") + ", the site key's handshake " +
                 (guard_->ready() ? "done" : "not done yet");
      }
      if (publishing && receiving) {
        {
          std::lock_guard lock(mutex_);
          if (!connected_now_) {
            const uint64_t now = monotonic_now_us();
            connected_now_ = true;
            if (!ever_connected_) {
              ever_connected_ = true, connected_us_ = now;
            } else if (other_left_count_ > 0) {
              ++rejoins_;
              last_away_s_ = double(now - left_us_) * 1e-6;
              last_reconnect_s_ = double(now - came_back_us_) * 1e-6;
            }
          }
        }
        flush_touches();
        if (std::chrono::steady_clock::now() >= next_heartbeat) {
          next_heartbeat = std::chrono::steady_clock::now() + session_.heartbeat_period;
          send(net::HeartbeatMessage{monotonic_now_us(), ++heartbeat_sequence_});
        }
      }
      if (!busy) std::this_thread::sleep_for(kJanusPumpPeriod);
    }
  } catch (const std::exception& e) {
    fail(e.what());
  }
}

void JanusLink::pump_received(bool& busy) {
  while (auto portrait = subscriber_->take_portrait()) {
    busy = true;
    {
      std::lock_guard lock(mutex_);
      ++counts_.messages_in[size_t(net::message_type_index(net::MessageType::Portrait))];
    }
    if (handler_) handler_(portrait->portrait);
  }
  for (const net::Message& message : subscriber_->take_messages()) {
    busy = true;
    {
      std::lock_guard lock(mutex_);
      ++counts_.messages_in[size_t(net::message_type_index(net::message_type(message)))];
    }
    if (handler_) handler_(message);
  }
}

void JanusLink::send(const net::Message& message) {
  const net::MessageType type = net::message_type(message);
  const size_t index = size_t(net::message_type_index(type));
  if (type == net::MessageType::Signal) throw std::invalid_argument("a signal has no place on a call set up through Janus");
  WebRtcPeer* peer = sending_.load();
  if (const auto* touch = std::get_if<net::TouchEventMessage>(&message)) {
    {
      std::lock_guard lock(mutex_);
      if (other_away_) {
        ++touches_dropped_away_;
        ++counts_.stale_dropped_out[index];
        return;
      }
    }
    touches_.add(*touch);
    if (peer) flush_touches();
    return;
  }
  bool sent = false;
  if (peer) {
    if (const auto* portrait = std::get_if<net::PortraitMessage>(&message)) {
      peer->send_portrait(*portrait);
      sent = true;
    } else {
      sent = peer->send_message(message);
    }
  }
  std::lock_guard lock(mutex_);
  ++(sent ? counts_.messages_out[index] : counts_.stale_dropped_out[index]);
}

void JanusLink::flush_touches() {
  WebRtcPeer* peer = sending_.load();
  if (!peer) return;
  const size_t sent = touches_.flush([peer](const net::TouchEventMessage& touch) { return peer->send_message(touch); });
  std::lock_guard lock(mutex_);
  counts_.messages_out[size_t(net::message_type_index(net::MessageType::TouchEvent))] += sent;
}

net::ConnectionStatus JanusLink::status() const {
  net::ConnectionStatus status;
  status.peer = "Janus room " + std::to_string(room_options_.room) + " at " + room_options_.url;
  std::lock_guard lock(mutex_);
  if (!failure_.empty() || !guard_->failure().empty()) {
    status.state = net::ConnectionState::Refused;
    status.reason = !failure_.empty() ? failure_ : guard_->failure();
  } else if (connected_now_) {
    status.state = net::ConnectionState::Connected;
    status.peer += " (WebRTC through Janus)";
  } else if (ever_connected_) {
    status.state = net::ConnectionState::Lost;
    status.reason = other_away_ ? "the other site left the room; waiting for it to come back"
                                : "the other site came back to the room; " + stage_;
  } else {
    status.state = net::ConnectionState::Connecting;
    status.reason = !my_id_                  ? "joining the room"
                    : other_away_            ? "the other site left the room before the call was up; waiting for it to come back"
                    : !subscriber_           ? "in the room; waiting for the other site to publish"
                                             : stage_;
  }
  return status;
}

net::NetCounters JanusLink::counters() const {
  std::lock_guard lock(mutex_);
  net::NetCounters out = counts_;
  out.touches_unacked_dropped += touches_.dropped();
  if (publisher_) {
    const WebRtcCounters sent = publisher_->counters();
    out.bytes_out += sent.color_bytes_sent + sent.depth_bytes_sent + sent.channel_bytes_sent;
  }
  WebRtcCounters received = retired_;
  if (subscriber_) add_receiving_counts(received, subscriber_->counters());
  out.rejected += received.messages_refused;
  if (received.messages_refused) {
    out.rejected_by_reason["webrtc_refused"] += received.messages_refused;
    out.last_rejection = subscriber_ && subscriber_->counters().messages_refused ? subscriber_->last_error() : failure_seen_;
  }
  return out;
}

nlohmann::json JanusLink::transport_json() const {
  std::lock_guard lock(mutex_);
  nlohmann::json out = {{"kind", "webrtc-janus"},
                        {"room", room_options_.room},
                        {"janus", room_options_.url},
                        {"this_site_id", my_id_},
                        {"other_site_id", other_id_},
                        {"connected_s", ever_connected_ ? double(monotonic_now_us() - connected_us_) * 1e-6 : 0.0},
                        {"data_channels_sealed", guard_->ready()},
                        {"other_site_left", other_left_count_},
                        {"other_site_rejoins", rejoins_},
                        {"other_site_away_now", other_away_},
                        {"last_rejoin_s", {{"away", last_away_s_}, {"back_to_connected", last_reconnect_s_}}},
                        {"touches_dropped_while_away", touches_dropped_away_},
                        {"last_error", failure_}};
  if (publisher_) {
    const WebRtcCounters sent = publisher_->counters();
    const WebRtcCounters now = subscriber_ ? subscriber_->counters() : WebRtcCounters{};
    WebRtcCounters received = retired_;
    add_receiving_counts(received, now);
    out["portraits"] = {{"sent", sent.portraits_sent}, {"received", received.portraits_received},
                        {"dropped", received.portraits_dropped}, {"frames_unpaired", received.frames_unpaired},
                        {"lost", received.portraits_lost}};
    out["messages"] = {{"sent", sent.messages_sent}, {"received", received.messages_received},
                       {"refused", received.messages_refused}, {"early_dropped", received.messages_early}};
    // What the call brought since the other site last came back (its present publication, or the
    // last one if it left again).
    if (rejoins_ > 0)
      out["since_rejoin"] = {{"portraits_received", received.portraits_received - before_rejoin_.portraits_received},
                             {"messages_received", received.messages_received - before_rejoin_.messages_received},
                             {"messages_refused", received.messages_refused - before_rejoin_.messages_refused}};
    out["codec_ms_median"] = {{"color_encode", sent.color_encode_ms}, {"depth_alpha_encode", sent.depth_encode_ms},
                              {"color_decode", now.color_decode_ms}, {"depth_alpha_decode", now.depth_decode_ms}};
    out["keyframes"] = {{"asked_by_us", received.keyframes_asked}, {"asked_of_us", sent.keyframes_asked_of_us}};
    out["kbit_out"] = {{"color_kbps_now", sent.color_kbps_now}, {"depth_kbps_now", sent.depth_kbps_now}};
    if (out["last_error"] == "")
      out["last_error"] = now.messages_refused ? subscriber_->last_error()
                          : received.messages_refused ? failure_seen_ : publisher_->last_error();
  }
  return out;
}

}  // namespace rt::media
