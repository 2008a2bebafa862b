#include "media/webrtc_link.h"

#include <stdexcept>

#include "media/pending_touches.h"
#include "time/monotonic_clock.h"

namespace rt::media {
namespace {

constexpr auto kLinkPumpPeriod = std::chrono::milliseconds(2);

// libnice skips loopback unless it is named: a call between two sites on one machine gathers on
// it alone, and a call between machines on every interface (there is no STUN server yet).
std::vector<std::string> ice_addresses_for(const std::string& session_host) {
  if (session_host == "127.0.0.1" || session_host == "localhost") return {"127.0.0.1"};
  if (session_host == "::1" || session_host == "[::1]") return {"::1"};
  return {};
}

// One track's figures for metrics.json: what it is sent at, what its codecs cost, what the network
// took from what it receives.
nlohmann::json track_json(int target_kbps, double encode_ms, double decode_ms, const WebRtcCounters::TrackLoss& loss) {
  return {{"bitrate_target_kbps", target_kbps}, {"encode_ms_median", encode_ms}, {"decode_ms_median", decode_ms},
          {"frames_lost", loss.frames_lost}, {"packets_lost_past_repair", loss.packets_lost},
          {"losses", loss.episodes}, {"recovered", loss.recovered}, {"recovery_ms_median", loss.recovery_ms_median},
          {"recovery_ms_max", loss.recovery_ms_max}, {"keyframes_asked", loss.keyframes_asked}};
}

// The voice track's: what it sent (Opus payload, as the sound's own figure counts it), what came and
// what the network took past repair (the site's jitter buffer conceals those: sound.voice.jitter).
nlohmann::json voice_json(const VoiceTrackCounters& voice, int jitter_buffer_ms, uint64_t refused, double seconds) {
  return {{"packets_sent", voice.packets_sent},
          {"kbit_per_s_out", seconds > 0 ? nlohmann::json(double(voice.bytes_sent) * 8e-3 / seconds) : nlohmann::json()},
          {"packets_received", voice.packets_received}, {"packets_lost_past_repair", voice.packets_lost},
          {"packets_refused", voice.packets_refused + refused}, {"packets_dropped", voice.packets_dropped},
          {"retransmission", voice.retransmission}, {"jitter_buffer_ms", jitter_buffer_ms}};
}

const char* signal_kind_name(net::SignalMessage::Kind kind) {
  return kind == net::SignalMessage::Kind::Offer ? "offer" : kind == net::SignalMessage::Kind::Answer ? "answer" : "candidate";
}

}  // namespace

WebRtcLink::WebRtcLink(net::SessionOptions session, WebRtcPeerOptions peer)
    : session_options_(std::move(session)), width_(peer.width), height_(peer.height), simulated_loss_(peer.simulated_loss),
      voice_jitter_buffer_ms_(peer.voice_jitter_buffer_ms) {
  const bool connector = session_options_.role == net::Role::Connector;
  peer.offerer = connector;
  peer.name = session_options_.name + " webrtc";
  if (peer.local_addresses.empty() || peer.local_addresses == std::vector<std::string>{"127.0.0.1"})
    peer.local_addresses = ice_addresses_for(session_options_.host);
  // The opener's limit: what a data-channel message may hold once its seal is off.
  guard_ = std::make_shared<ChannelGuard>(session_options_.key, session_options_.role, 64 * 1024 - net::kDatagramOverhead);
  peer.guard = guard_;
  Signalling signalling;
  // From GStreamer's threads: the session queues them for its network thread.
  signalling.on_description = [this](const std::string& type, const std::string& sdp) {
    session_->send(net::SignalMessage{type == "offer" ? net::SignalMessage::Kind::Offer : net::SignalMessage::Kind::Answer, 0, sdp});
  };
  signalling.on_candidate = [this](unsigned mline, const std::string& candidate) {
    session_->send(net::SignalMessage{net::SignalMessage::Kind::Candidate, mline, candidate});
  };
  session_ = std::make_unique<net::Session>(session_options_);
  peer_ = std::make_unique<WebRtcPeer>(peer, signalling);
  session_->set_handler([this](const net::Message& message) { on_session_message(message); });
}

WebRtcLink::~WebRtcLink() {
  stop();
  // The session's thread, which calls into the peer, ended in stop(); the peer goes first, so
  // that no GStreamer thread sends a signal into a session that is gone.
  peer_.reset();
  session_.reset();
}

void WebRtcLink::start() {
  if (started_.exchange(true)) throw std::logic_error("a link starts once");
  session_->start();
  pump_thread_ = std::thread([this] { pump(); });
}

void WebRtcLink::stop() {
  if (stopping_.exchange(true)) return;
  if (pump_thread_.joinable()) pump_thread_.join();
  if (session_) session_->stop();
}

uint16_t WebRtcLink::local_port() const { return session_->local_port(); }

void WebRtcLink::set_handler(std::function<void(const net::Message&)> handler) { handler_ = std::move(handler); }

void WebRtcLink::on_session_message(const net::Message& message) {
  const auto* signal = std::get_if<net::SignalMessage>(&message);
  if (!signal) return;  // the session's heartbeats; nothing else travels on it in this mode
  std::string error;
  if (signal->kind == net::SignalMessage::Kind::Candidate)
    peer_->add_ice_candidate(signal->mline, signal->text);
  else
    error = peer_->set_remote_description(signal_kind_name(signal->kind), signal->text);
  std::lock_guard lock(mutex_);
  ++counts_.messages_in[size_t(net::message_type_index(net::MessageType::Signal))];
  if (!error.empty() && signal_error_.empty())
    signal_error_ = std::string("the other site's WebRTC ") + signal_kind_name(signal->kind) + " was refused: " + error;
}

void WebRtcLink::send(const net::Message& message) {
  const net::MessageType type = net::message_type(message);
  const size_t index = size_t(net::message_type_index(type));
  if (const auto* portrait = std::get_if<net::PortraitMessage>(&message)) {
    peer_->send_portrait(*portrait);
    std::lock_guard lock(mutex_);
    ++counts_.messages_out[index];
    return;
  }
  if (type == net::MessageType::Signal) {
    session_->send(message);
    return;
  }
  if (const auto* voice = std::get_if<net::VoiceMessage>(&message)) {
    const bool sent = peer_->send_voice(voice->packet, voice->timestamp_us, voice->frame_samples);
    std::lock_guard lock(mutex_);
    ++(sent ? counts_.messages_out[index] : counts_.stale_dropped_out[index]);
    return;
  }
  if (const auto* touch = std::get_if<net::TouchEventMessage>(&message)) {
    touches_.add(*touch);
    flush_touches();
    return;
  }
  const bool sent = peer_->send_message(message);
  std::lock_guard lock(mutex_);
  ++(sent ? counts_.messages_out[index] : counts_.stale_dropped_out[index]);
}

void WebRtcLink::flush_touches() {
  const size_t sent = touches_.flush([this](const net::TouchEventMessage& touch) { return peer_->send_message(touch); });
  std::lock_guard lock(mutex_);
  counts_.messages_out[size_t(net::message_type_index(net::MessageType::TouchEvent))] += sent;
}

void WebRtcLink::pump() {
  bool blank_sent = false;
  auto next_heartbeat = std::chrono::steady_clock::now();
  while (!stopping_) {
    // The offerer's first picture lets webrtcbin make the offer; it waits for the session, whose
    // network thread then carries the offer across.
    if (!blank_sent && session_->status().connected()) {
      if (peer_->connected() == false && session_options_.role == net::Role::Connector)
        peer_->send_portrait(blank_portrait(width_, height_));
      blank_sent = true;
    }
    bool busy = false;
    while (auto portrait = peer_->take_portrait()) {
      busy = true;
      {
        std::lock_guard lock(mutex_);
        ++counts_.messages_in[size_t(net::message_type_index(net::MessageType::Portrait))];
      }
      if (handler_) handler_(portrait->portrait);
    }
    for (const net::Message& message : peer_->take_messages()) {
      busy = true;
      {
        std::lock_guard lock(mutex_);
        ++counts_.messages_in[size_t(net::message_type_index(net::message_type(message)))];
        if (const auto* heartbeat = std::get_if<net::HeartbeatMessage>(&message)) peer_clock_us_ = heartbeat->timestamp_us;
      }
      if (handler_) handler_(message);
    }
    std::optional<uint64_t> peer_clock;
    {
      std::lock_guard lock(mutex_);
      peer_clock = peer_clock_us_;
    }
    if (peer_clock)
      for (const ReceivedVoice& received : peer_->take_voice()) {
        busy = true;
        const std::optional<net::VoiceMessage> voice = voice_message_of(received, *peer_clock);
        {
          std::lock_guard lock(mutex_);
          ++(voice ? counts_.messages_in[size_t(net::message_type_index(net::MessageType::Voice))] : voice_refused_);
        }
        if (voice && handler_) handler_(*voice);
      }
    const bool up = peer_->connected();  // also sends the guard's hello once the channels open
    if (up) {
      {
        std::lock_guard lock(mutex_);
        if (!ever_connected_) ever_connected_ = true, connected_us_ = monotonic_now_us();
      }
      flush_touches();
      if (std::chrono::steady_clock::now() >= next_heartbeat) {
        next_heartbeat = std::chrono::steady_clock::now() + session_options_.heartbeat_period;
        net::HeartbeatMessage heartbeat{monotonic_now_us(), ++heartbeat_sequence_};
        send(heartbeat);
      }
    }
    if (!busy) std::this_thread::sleep_for(kLinkPumpPeriod);
  }
}

net::ConnectionStatus WebRtcLink::status() const {
  net::ConnectionStatus status = session_->status();
  const std::string guard_failure = guard_->failure();
  std::string signal_error;
  {
    std::lock_guard lock(mutex_);
    signal_error = signal_error_;
  }
  if (status.state == net::ConnectionState::Ended) return status;  // the other site said goodbye
  if (!signal_error.empty() || !guard_failure.empty()) {
    status.state = net::ConnectionState::Refused;
    status.reason = !signal_error.empty() ? signal_error : guard_failure;
    return status;
  }
  // The call, once up, does not need the session: it only set it up and will say goodbye.
  if (peer_->connected()) {
    status.state = net::ConnectionState::Connected;
    status.peer += " (WebRTC)";
  } else if (status.state == net::ConnectionState::Connected) {
    status.state = net::ConnectionState::Connecting;
    status.reason = "the session is up; the WebRTC call is being set up (the other site needs --transport webrtc too)";
  }
  return status;
}

net::NetCounters WebRtcLink::counters() const {
  net::NetCounters out = session_->counters();
  const WebRtcCounters call = peer_->counters();
  std::lock_guard lock(mutex_);
  for (int i = 0; i < net::kMessageTypeCount; ++i) {
    out.messages_in[size_t(i)] += counts_.messages_in[size_t(i)];
    out.messages_out[size_t(i)] += counts_.messages_out[size_t(i)];
    out.stale_dropped_out[size_t(i)] += counts_.stale_dropped_out[size_t(i)];
  }
  out.touches_unacked_dropped += touches_.dropped();
  out.bytes_out += call.color_bytes_sent + call.depth_bytes_sent + call.channel_bytes_sent + call.voice.bytes_sent;
  out.rejected += call.messages_refused;
  if (call.messages_refused) {
    out.rejected_by_reason["webrtc_refused"] += call.messages_refused;
    out.last_rejection = peer_->last_error();
  }
  return out;
}

nlohmann::json WebRtcLink::transport_json() const {
  const WebRtcCounters call = peer_->counters();
  uint64_t since_us = 0;
  {
    std::lock_guard lock(mutex_);
    since_us = ever_connected_ ? connected_us_ : 0;
  }
  const double seconds = since_us ? double(monotonic_now_us() - since_us) * 1e-6 : 0.0;
  uint64_t voice_refused = 0;
  {
    std::lock_guard lock(mutex_);
    voice_refused = voice_refused_;
  }
  auto kbps = [&](uint64_t bytes) { return seconds > 0 ? nlohmann::json(double(bytes) * 8e-3 / seconds) : nlohmann::json(); };
  return {{"kind", "webrtc"},
          {"connected_s", seconds},
          {"kbit_per_s_out", {{"color", kbps(call.color_bytes_sent)}, {"depth_alpha", kbps(call.depth_bytes_sent)}, {"voice", kbps(call.voice.bytes_sent)},
                              {"data_channels", kbps(call.channel_bytes_sent)}}},
          {"portraits", {{"sent", call.portraits_sent}, {"received", call.portraits_received},
                         {"dropped", call.portraits_dropped}, {"frames_unpaired", call.frames_unpaired}}},
          {"messages", {{"sent", call.messages_sent}, {"received", call.messages_received}, {"refused", call.messages_refused}, {"early_dropped", call.messages_early}}},
          {"codec_ms_median", {{"color_encode", call.color_encode_ms}, {"depth_alpha_encode", call.depth_encode_ms},
                               {"color_decode", call.color_decode_ms}, {"depth_alpha_decode", call.depth_decode_ms}}},
          {"keyframes", {{"asked_by_us", call.keyframes_asked}, {"asked_of_us", call.keyframes_asked_of_us}}},
          {"tracks", {{"color", track_json(call.color_kbps_now, call.color_encode_ms, call.color_decode_ms, call.color_loss)},
                      {"depth_alpha", track_json(call.depth_kbps_now, call.depth_encode_ms, call.depth_decode_ms, call.depth_loss)},
                      {"voice", voice_json(call.voice, voice_jitter_buffer_ms_, voice_refused, seconds)}}},
          {"network", {{"bitrate_decisions", call.bitrate_decisions}, {"reported_loss", call.reported_fraction_lost},
                       {"round_trip_ms", call.round_trip_ms >= 0 ? nlohmann::json(call.round_trip_ms) : nlohmann::json()},
                       {"bitrate_lowered", call.bitrate_lowered}, {"bitrate_raised", call.bitrate_raised},
                       {"portrait_size_sent", {call.width_sent, call.height_sent}},
                       {"size_steps_down", call.size_steps_down}, {"size_steps_up", call.size_steps_up},
                       {"pictures_scaled_up", {{"color", call.color_pictures_scaled}, {"depth_alpha", call.depth_pictures_scaled}}},
                       {"portraits_lost", call.portraits_lost}, {"simulated_loss", simulated_loss_ >= 0 ? nlohmann::json(simulated_loss_) : nlohmann::json()}}},
          {"retransmission", {{"asked", call.repair.retransmissions_asked}, {"arrived", call.repair.retransmissions_arrived},
                              {"given_up", call.repair.packets_given_up}, {"late", call.repair.packets_late},
                              {"asked_of_us", call.repair.retransmissions_requested_of_us},
                              {"resent", call.repair.retransmissions_sent}}},
          {"data_channels_sealed", guard_->ready()},
          {"last_error", peer_->last_error()}};
}

}  // namespace rt::media
