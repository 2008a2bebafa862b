#include "media/janus_link.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "media/pending_touches.h"
#include "net/datagram_seal.h"
#include "time/monotonic_clock.h"

namespace rt::media {
namespace {

constexpr auto kJanusPumpPeriod = std::chrono::milliseconds(2);
// The connection to Janus lost: tried again after a wait that doubles up to a ceiling, a bounded
// number of times. A restarted Janus answers again soon, so the first tries come quickly; one gone
// for good is reported as such rather than waited on for the rest of the run.
constexpr int kJanusAttempts = 10;
constexpr auto kJanusFirstRetry = std::chrono::milliseconds(250), kJanusLongestRetry = std::chrono::milliseconds(4000);

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
  subscribed_in_room_ = false;
  const uint64_t me = room_->join();
  WebRtcPeerOptions publishing = peer_options_;
  publishing.name = session_.name + " publisher";
  publishing.offerer = true;
  auto publisher = std::make_unique<WebRtcPeer>(publishing, signalling(JanusRoom::Peer::Publisher));
  {
    std::unique_lock hold(publisher_mutex_);
    std::lock_guard lock(mutex_);
    my_id_ = me;
    publisher_ = std::move(publisher);
    sending_ = publisher_.get();
  }
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
  if (subscribed_in_room_) room_->renew_subscriber_handle();
  subscribed_in_room_ = true;
  bool again = false, set_up_again = false;
  {
    std::lock_guard lock(mutex_);
    again = coming_back_ == ComingBack::OtherSite;
    set_up_again = coming_back_ != ComingBack::No;
  }
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
  if (again) came_back_us_ = monotonic_now_us();
  if (set_up_again) before_rejoin_ = retired_;
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

void add_sending_counts(WebRtcCounters& into, const WebRtcCounters& from) {
  into.portraits_sent += from.portraits_sent;
  into.messages_sent += from.messages_sent;
  into.color_bytes_sent += from.color_bytes_sent;
  into.depth_bytes_sent += from.depth_bytes_sent;
  into.channel_bytes_sent += from.channel_bytes_sent;
  into.keyframes_asked_of_us += from.keyframes_asked_of_us;
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
    if (coming_back_ != ComingBack::Janus) coming_back_ = ComingBack::OtherSite;
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
  int attempt = 0;
  while (!stopping_) {
    try {
      set_up();
      {
        std::lock_guard lock(mutex_);
        if (!janus_lost_.empty()) ++janus_rejoins_, janus_lost_.clear(), janus_retry_error_.clear();
      }
      attempt = 0;
      call();
      return;
    } catch (const std::exception& e) {
      // Only a connection to Janus that worked and was lost is tried again: a refusal at the start
      // (a wrong pin, no such room, no Janus there) is the user's to see at once.
      const bool lost = room_ && room_->closed();
      std::string lost_why;
      {
        std::lock_guard lock(mutex_);
        lost_why = janus_lost_;
      }
      if (lost_why.empty() && !lost) return fail(e.what());
      if (++attempt > kJanusAttempts)
        return fail("the connection to Janus was lost (" + lost_why + ") and could not be set up again in " +
                    std::to_string(kJanusAttempts) + " tries: " + e.what());
      const auto delay = std::min<std::chrono::milliseconds>(kJanusFirstRetry * (1 << std::min(attempt - 1, 8)), kJanusLongestRetry);
      leave_janus(lost_why.empty() ? room_->closed_reason() : lost_why, lost_why.empty() ? "" : e.what(), attempt, delay);
      for (const auto until = std::chrono::steady_clock::now() + delay; !stopping_ && std::chrono::steady_clock::now() < until;)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}

// Janus is gone (restarted, the WebSocket closed): the peers, the room and the guard's
// handshake with it. The next try makes all of them again; the other site, which lost Janus
// too, does the same, and the two meet in the room again.
void JanusLink::leave_janus(const std::string& why, const std::string& retry_error, int attempt, std::chrono::milliseconds delay) {
  std::unique_ptr<WebRtcPeer> publisher, subscriber;
  {
    std::unique_lock hold(publisher_mutex_);  // no send() is using the publisher past this
    std::lock_guard lock(mutex_);
    if (subscriber_) add_receiving_counts(retired_, subscriber_->counters());
    if (publisher_) add_sending_counts(retired_sent_, publisher_->counters());
    subscriber = std::move(subscriber_);
    publisher = std::move(publisher_);
    sending_ = nullptr;
    said_.clear();
    if (janus_lost_.empty()) janus_lost_us_ = monotonic_now_us(), ++janus_lost_count_;
    janus_lost_ = why;
    janus_retry_error_ = retry_error;
    janus_attempt_ = attempt;
    janus_next_try_us_ = monotonic_now_us() + uint64_t(delay.count()) * 1000;
    connected_now_ = false;
    other_away_ = true;
    coming_back_ = ComingBack::Janus;
  }
  const size_t dropped = touches_.drop_all();
  {
    std::lock_guard lock(mutex_);
    touches_dropped_away_ += dropped;
  }
  // The peers before the room (their GStreamer threads call its trickle), the guard last.
  subscriber.reset();
  publisher.reset();
  room_.reset();
  guard_->reset();
}

void JanusLink::call() {
  auto next_heartbeat = std::chrono::steady_clock::now();
  while (!stopping_) {
    if (room_->closed()) throw std::runtime_error(room_->closed_reason());
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
          } else if (coming_back_ == ComingBack::OtherSite) {
            ++rejoins_;
            last_away_s_ = double(now - left_us_) * 1e-6;
            last_reconnect_s_ = double(now - came_back_us_) * 1e-6;
          } else if (coming_back_ == ComingBack::Janus) {
            last_janus_outage_s_ = double(now - janus_lost_us_) * 1e-6;
          }
          coming_back_ = ComingBack::No;
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
  std::shared_lock hold(publisher_mutex_);  // the publisher outlives this call
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
    flush_touches_to(peer);
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
  std::shared_lock hold(publisher_mutex_);
  flush_touches_to(sending_.load());
}

void JanusLink::flush_touches_to(WebRtcPeer* peer) {
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
  } else if (!janus_lost_.empty()) {
    status.state = ever_connected_ ? net::ConnectionState::Lost : net::ConnectionState::Connecting;
    const uint64_t now = monotonic_now_us();
    char wait[32];
    std::snprintf(wait, sizeof wait, "%.1f", now < janus_next_try_us_ ? double(janus_next_try_us_ - now) * 1e-6 : 0.0);
    status.reason = "the connection to Janus was lost (" + janus_lost_ + "); joining the room again, try " +
                    std::to_string(janus_attempt_) + " of " + std::to_string(kJanusAttempts) +
                    (now < janus_next_try_us_ ? std::string(" in ") + wait + " s" : std::string(" now")) +
                    (janus_retry_error_.empty() ? "" : " (the last: " + janus_retry_error_ + ")");
  } else if (connected_now_) {
    status.state = net::ConnectionState::Connected;
    status.peer += " (WebRTC through Janus)";
  } else if (ever_connected_) {
    status.state = net::ConnectionState::Lost;
    const bool after_janus = coming_back_ == ComingBack::Janus;
    status.reason = other_away_ ? (after_janus ? "back in the room after the connection to Janus was lost; waiting for the other site to publish again"
                                               : "the other site left the room; waiting for it to come back")
                                : (after_janus ? "both sites back in the room after the connection to Janus was lost; "
                                               : "the other site came back to the room; ") + stage_;
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
  WebRtcCounters sent = retired_sent_;
  if (publisher_) add_sending_counts(sent, publisher_->counters());
  out.bytes_out += sent.color_bytes_sent + sent.depth_bytes_sent + sent.channel_bytes_sent;
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
                        {"janus_lost", janus_lost_count_},
                        {"janus_rejoins", janus_rejoins_},
                        {"last_janus_outage_s", last_janus_outage_s_},
                        {"last_error", failure_}};
  if (publisher_ || retired_sent_.portraits_sent) {
    WebRtcCounters sent = retired_sent_;
    const WebRtcCounters live = publisher_ ? publisher_->counters() : WebRtcCounters{};
    add_sending_counts(sent, live);
    sent.color_encode_ms = live.color_encode_ms, sent.depth_encode_ms = live.depth_encode_ms;
    sent.color_kbps_now = live.color_kbps_now, sent.depth_kbps_now = live.depth_kbps_now;
    const WebRtcCounters now = subscriber_ ? subscriber_->counters() : WebRtcCounters{};
    WebRtcCounters received = retired_;
    add_receiving_counts(received, now);
    out["portraits"] = {{"sent", sent.portraits_sent}, {"received", received.portraits_received},
                        {"dropped", received.portraits_dropped}, {"frames_unpaired", received.frames_unpaired},
                        {"lost", received.portraits_lost}};
    out["messages"] = {{"sent", sent.messages_sent}, {"received", received.messages_received},
                       {"refused", received.messages_refused}, {"early_dropped", received.messages_early}};
    // What the call brought since it was last set up again (the other site back, or both back
    // after Janus was lost), up to now or to its end if it ended again.
    if (rejoins_ > 0 || janus_rejoins_ > 0)
      out["since_rejoin"] = {{"portraits_received", received.portraits_received - before_rejoin_.portraits_received},
                             {"messages_received", received.messages_received - before_rejoin_.messages_received},
                             {"messages_refused", received.messages_refused - before_rejoin_.messages_refused}};
    out["codec_ms_median"] = {{"color_encode", sent.color_encode_ms}, {"depth_alpha_encode", sent.depth_encode_ms},
                              {"color_decode", now.color_decode_ms}, {"depth_alpha_decode", now.depth_decode_ms}};
    out["keyframes"] = {{"asked_by_us", received.keyframes_asked}, {"asked_of_us", sent.keyframes_asked_of_us}};
    out["kbit_out"] = {{"color_kbps_now", sent.color_kbps_now}, {"depth_kbps_now", sent.depth_kbps_now}};
    if (out["last_error"] == "")
      out["last_error"] = now.messages_refused ? subscriber_->last_error()
                          : received.messages_refused ? failure_seen_
                          : publisher_                ? publisher_->last_error()
                                                      : janus_lost_;
  }
  return out;
}

}  // namespace rt::media
