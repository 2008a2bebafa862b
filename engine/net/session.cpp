#include "net/session.h"

#include <pthread.h>
#include <sodium.h>
#include <sys/socket.h>
#include <unistd.h>

#include <asio.hpp>
#include <algorithm>
#include <condition_variable>
#include <deque>
#include <iostream>
#include <mutex>
#include <set>
#include <thread>

#include "net/connection_rate_limit.h"
#include "net/log_limit.h"
#include "net/session_connection.h"
#include "time/monotonic_clock.h"

namespace rt::net {

namespace {

using asio::ip::tcp;

using session_detail::Connection;
using session_detail::ConnectionPtr;

// Connections whose hello has not come yet: strangers open them at will (within their network's
// rate), so their number is bounded, and room is made by closing the oldest, but never one
// younger than kHelloGrace (its hello, sent with the connection, is on its way: this is what lets
// the real peer's connection live to be read under a flood), and never one from the address the
// peer last authenticated from for a stranger's. With every one younger, the newcomer is closed:
// at most kMaxAwaitingHello / kHelloGrace new connections a second get past accept, whatever
// the number of networks they come from.
constexpr size_t kMaxAwaitingHello = 256;
constexpr uint64_t kHelloGraceUs = 250'000;
// Handshakes under way (an authentic hello came, a key pair was made): only a holder of the key
// gets here, so a few suffice; the oldest goes for the newest (a reconnecting peer's stale one).
constexpr size_t kMaxPendingHandshakes = 4;
// New handshakes a second, in all: a holder of the key reconnects a few times a second at most.
constexpr uint32_t kNewHandshakesPerSecond = 20;

// New connections a network may open while it is not the authenticated peer's address: a
// connector retries a few times a second at most, so beyond this it is a flood, and its
// connections are closed at accept, unread. Remembering a network costs little; how many is bounded.
constexpr uint32_t kNewConnectionsPerSecondPerAddress = 10;
constexpr uint32_t kNewConnectionBurstPerAddress = 20;
constexpr size_t kRateLimitedAddresses = 1024;
// A round of accepting ends after this many even with more waiting, so that the network thread
// also serves the live connection and its timers under a flood that never lets the backlog empty.
constexpr int kMaxAcceptsPerRound = 256;
constexpr std::chrono::milliseconds kShedPause{5};

// What leaves next, chosen under the queue lock.
struct Outgoing {
  MessageType type;
  std::vector<uint8_t> bytes;
  uint64_t touch_sequence = 0;  // nonzero: a touch event, written up to here once out
  bool goodbye = false;         // the heartbeat that ends the session: close once it is out
};

// How long a session that stops waits for its goodbye to be written (behind a portrait, say).
constexpr std::chrono::milliseconds kGoodbyeWait{300};

// Unacknowledged touch events a session keeps for sending again; touches are a few a second, so
// only a peer that never acknowledges fills it.
constexpr size_t kMaxUnackedTouches = 256;
// A WebRTC call's set-up is an offer, an answer and a few dozen candidates at most.
constexpr size_t kMaxQueuedSignals = 256;

}  // namespace

struct Session::Impl {
  explicit Impl(SessionOptions o)
      : options(std::move(o)), hello_gate(options.key), acceptor(io), connect_timer(io), tick_timer(io), accept_timer(io),
        goodbye_timer(io) {
    ensure_sodium();
    if (is_weak_session_key(options.key))
      throw std::invalid_argument(
          "session key is weak (too regular to be a secret, e.g. all zero or hand-typed): make one with remotetouch keygen FILE");
    if (!options.log) options.log = [](const std::string& line) { std::cerr << line << "\n"; };
    do randombytes_buf(&touch_session, sizeof touch_session);
    while (touch_session == 0);
  }

  SessionOptions options;
  HelloGate hello_gate;  // the listener's: MAC and replay window of the connectors' hellos
  asio::io_context io;  // destroyed after everything below that uses it
  tcp::acceptor acceptor;
  asio::steady_timer connect_timer, tick_timer, accept_timer, goodbye_timer;
  // Accept errors (no descriptors left, say) persist until something closes: waiting before the
  // next accept, longer each time, keeps the loop from spinning, and one log line a second says
  // how many there were.
  std::chrono::milliseconds accept_backoff{0};
  uint64_t accept_errors_unlogged = 0;
  std::chrono::steady_clock::time_point accept_error_logged{};
  ConnectionRateLimit connection_rate{kNewConnectionsPerSecondPerAddress, kNewConnectionBurstPerAddress,
                                      kRateLimitedAddresses};
  ConnectionRateLimit handshake_rate{kNewHandshakesPerSecond, kNewHandshakesPerSecond, 1};
  // The address the peer last authenticated from (its bytes): its reconnections are never shed,
  // even while a stranger on the same address floods us.
  std::string peer_address_key;
  int listener_fd_paused = -1;  // the listening socket while it sits out a pause in shedding a flood
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work;
  std::thread thread;
  bool closing = false;  // network thread only
  bool goodbye_pending = false;  // network thread only: stopping, the goodbye not yet written
  std::set<ConnectionPtr> connections;
  ConnectionPtr active;
  int backoff_attempt = 0;
  bool ever_connected = false;
  uint64_t attempts_failed_while_lost = 0;  // since the session was last lost, not yet logged
  std::string last_failed_attempt;
  uint64_t heartbeat_sequence = 0;
  uint16_t bound_port = 0;
  std::function<void(const Message&)> handler;

  mutable std::mutex mutex;  // everything below
  std::optional<std::vector<uint8_t>> out_eye, out_skeleton, out_portrait, out_heartbeat;
  // Touch events sent and not yet acknowledged by the peer, by sequence, oldest first.
  std::deque<std::pair<uint64_t, std::vector<uint8_t>>> out_touch;
  // WebRTC signals, each needed (an offer, an answer, every candidate): queued, not newest-wins,
  // on the current connection only (a call set up over a connection that died is set up again).
  std::deque<std::vector<uint8_t>> out_signal;
  uint64_t touch_session = 0;  // random: tells this run's touch sequence from an earlier run's
  uint64_t next_touch_sequence = 1;
  uint64_t touches_written_any = 0;  // the newest touch event written on any connection
  // The newest touch event received, by the sending session and its sequence: acknowledged in
  // every heartbeat, and older copies dropped.
  uint64_t peer_touch_session = 0, peer_touch_sequence = 0;
  std::optional<EyeMessage> in_eye;
  std::optional<PortraitMessage> in_portrait;
  std::optional<SkeletonMessage> in_skeleton;
  std::optional<HeartbeatMessage> in_heartbeat;
  std::vector<TouchEventMessage> in_touch;
  // Voice frames queue in order: each is a different 20 ms of speech, none replaces another. Both
  // queues are bounded; past that the oldest frame goes (counted as stale), and the receiver's
  // jitter buffer conceals it.
  std::deque<std::vector<uint8_t>> out_voice;
  ConnectionStatus status;
  NetCounters counters;

  // Portraits are decoded on a thread of their own (tens of ms at 720p), so that touch events,
  // eyes and skeletons behind one on the socket are not held up. Newest wins here too.
  std::thread portrait_thread;
  std::condition_variable portrait_wake;
  std::optional<std::vector<uint8_t>> portrait_pending;  // under `mutex`
  bool portrait_stop = false;                            // under `mutex`

  void log(const std::string& line) { options.log("[" + options.name + "] " + line); }
  LogLimit log_limited{[this](const std::string& line) { log(line); }};

  void set_status(ConnectionState state, std::string reason, std::string peer) {
    std::lock_guard lock(mutex);
    if (status.state != state) status.since_us = monotonic_now_us();  // "lost since T" survives retries
    status.state = state;
    status.reason = std::move(reason);
    if (!peer.empty()) status.peer = std::move(peer);
  }

  template <typename F>
  void count(F&& f) {
    std::lock_guard lock(mutex);
    f(counters);
  }

  void reject(const std::string& reason_key, const std::string& line) {
    log_limited("rejected " + reason_key, "rejected: " + line);
    count([&](NetCounters& c) {
      ++c.rejected;
      ++c.rejected_by_reason[reason_key];
      c.last_rejection = line;
    });
  }

  // ---- connection lifecycle (network thread) ----

  // Room for a new connection from `address_key` among those whose hello has not come yet (see
  // kMaxAwaitingHello): false when none can be made, and the newcomer is to be closed.
  bool make_room_for_hello(const std::string& newcomer_key, uint64_t now_us) {
    if (connections.size() < kMaxAwaitingHello) return true;  // they are among the connections
    const bool newcomer_is_peer = !peer_address_key.empty() && newcomer_key == peer_address_key;
    size_t awaiting = 0;
    ConnectionPtr oldest;
    for (const auto& c : connections) {
      if (c == active || c->closed || c->hello_authentic) continue;
      ++awaiting;
      if (!newcomer_is_peer && !peer_address_key.empty() && c->address_key == peer_address_key) continue;
      if (now_us - c->opened_us < kHelloGraceUs) continue;
      if (!oldest || c->opened_us < oldest->opened_us) oldest = c;
    }
    if (awaiting < kMaxAwaitingHello) return true;
    if (!oldest) {
      count([](NetCounters& k) { ++k.connections_turned_away; });
      log_limited("turned away", [] {
        return "new connections closed at accept: " + std::to_string(kMaxAwaitingHello) +
               " connections already wait for their hello, each for less than " + std::to_string(kHelloGraceUs / 1000) + " ms";
      });
      return false;
    }
    count([](NetCounters& k) { ++k.handshakes_dropped_for_room; });
    log_limited("handshake dropped", [&] {
      return "connection with " + oldest->peer + " dropped: too many connections wait for their hello";
    });
    close(oldest);
    return true;
  }

  // Room for one more handshake whose hello was authentic: the oldest under way goes.
  void make_room_for_handshake() {
    std::vector<ConnectionPtr> pending;
    for (const auto& c : connections)
      if (c != active && !c->closed && c->handshake) pending.push_back(c);
    if (pending.size() < kMaxPendingHandshakes) return;
    const ConnectionPtr oldest =
        *std::min_element(pending.begin(), pending.end(), [](const auto& a, const auto& b) { return a->opened_us < b->opened_us; });
    count([](NetCounters& k) { ++k.handshakes_dropped_for_room; });
    log_limited("handshake dropped", "handshake with " + oldest->peer + " dropped: too many handshakes under way");
    close(oldest);
  }

  // The connector's authenticated hello, before anything is spent on it: the MAC, the replay
  // window, the rate of new handshakes. Empty when it may go on.
  std::optional<std::string> check_connector_hello(const ConnectionPtr& c) {
    switch (hello_gate.check(c->hello_in)) {
      case HelloVerdict::NotAuthentic:
        count([](NetCounters& k) { ++k.hellos_not_authentic; });
        return "handshake: the hello is not authenticated with our session key (a stranger, or the wrong key on one side)";
      case HelloVerdict::Replayed:
        count([](NetCounters& k) { ++k.hellos_replayed; });
        return "handshake: the hello is no later than the last one accepted (replayed, or the peer's clock went back)";
      case HelloVerdict::Accepted: break;
    }
    if (!handshake_rate.admit({}, monotonic_now_us()))
      return "handshake: more than " + std::to_string(kNewHandshakesPerSecond) + " new handshakes a second";
    c->hello_authentic = true;
    make_room_for_handshake();
    return std::nullopt;
  }

  void begin(const ConnectionPtr& c) {
    std::error_code ec;
    c->socket.set_option(tcp::no_delay(true), ec);
    const auto endpoint = c->socket.remote_endpoint(ec);
    c->address = ec ? "?" : endpoint.address().to_string();
    if (!ec) c->address_key = address_key(endpoint.address());
    c->peer = ec ? "?" : c->address + ":" + std::to_string(endpoint.port());
    if (!c->opened_us) c->opened_us = monotonic_now_us();
    connections.insert(c);
    // The connector says hello at once; the listener only to a connector whose hello proved the
    // key, so that a stranger costs it no key pair, no write, and learns nothing keyed.
    if (options.role == Role::Connector) say_hello(c);
    c->handshake_timer.expires_after(options.handshake_timeout);
    c->handshake_timer.async_wait([this, c](std::error_code e) {
      if (e || c->closed) return;
      if (c->refused) return close(c);  // the decoy never went out
      if (!c->handshake || !c->handshake->complete()) refuse(c, "handshake timed out", false);
    });
    // The hello's first bytes alone first: a peer of another version gets a clear error, not a
    // wait for the rest of a hello that may be shorter than ours.
    asio::async_read(c->socket, asio::buffer(c->hello_in.data(), kHelloPrefixSize), [this, c](std::error_code e, size_t n) {
      count([&](NetCounters& k) { k.bytes_in += n; });
      if (c->closed || c->refused) return;
      // A listener that read our hello and closed did not take it; one that closes unread (a
      // reset) is shedding connections, a temporary state.
      // Once our key has worked with this listener, a close while the session is being rebuilt
      // is the link still down (an outage, a proxy), not a refusal of the key.
      if (e == asio::error::eof && options.role == Role::Connector)
        return refuse(c,
                      "the listener closed the connection without a hello: it did not take ours (the wrong session key "
                      "on one side?), or it is turning connections away",
                      !ever_connected);
      if (e) return refuse(c, "peer closed during the handshake (" + e.message() + ")", false);
      const auto prefix = std::span(c->hello_in).first(kHelloPrefixSize);
      if (auto error = Handshake::check_hello_prefix(prefix, options.role)) {
        // A RemoteTouch peer of another version learns ours from our hello's first bytes.
        if (options.role == Role::Listener && Handshake::has_hello_magic(prefix)) {
          const auto ours = Handshake::hello_prefix(options.role);
          c->handshake_out.emplace_back(ours.begin(), ours.end());
        }
        return refuse(c, *error);
      }
      asio::async_read(c->socket, asio::buffer(c->hello_in.data() + kHelloPrefixSize, kHelloSize - kHelloPrefixSize),
                       [this, c](std::error_code e2, size_t n2) {
                         count([&](NetCounters& k) { k.bytes_in += n2; });
                         if (c->closed || c->refused) return;
                         if (e2) return refuse(c, "peer closed during the handshake (" + e2.message() + ")", false);
                         if (options.role == Role::Listener) {
                           if (auto error = check_connector_hello(c)) return refuse(c, *error);
                           say_hello(c);
                         }
                         if (auto error = c->handshake->receive_hello(c->hello_in)) return refuse(c, *error);
                         on_hello(c);
                       });
    });
  }

  void say_hello(const ConnectionPtr& c) {
    c->handshake = std::make_unique<Handshake>(options.key, options.role);
    count([](NetCounters& k) { ++k.handshakes_started; });
    const auto hello = c->handshake->hello();
    c->handshake_out.emplace_back(hello.begin(), hello.end());
    pump(c);
  }

  // The connector proves the key first; the listener proves it only to a connector that has.
  void on_hello(const ConnectionPtr& c) {
    if (options.role == Role::Connector) {
      const auto proof = c->handshake->proof();
      c->handshake_out.emplace_back(proof.begin(), proof.end());
      pump(c);
    }
    asio::async_read(c->socket, asio::buffer(c->proof_in), [this, c](std::error_code e, size_t n) {
      count([&](NetCounters& k) { k.bytes_in += n; });
      if (c->closed || c->refused) return;
      if (e)
        return refuse(c,
                      "handshake refused: the peer closed before proving the session key (" + e.message() +
                          "; wrong key on one side?)",
                      false);
      if (auto error = c->handshake->verify_proof(c->proof_in)) {
        if (options.role == Role::Listener) {
          const auto decoy = Handshake::decoy_proof();
          c->handshake_out.emplace_back(decoy.begin(), decoy.end());
        }
        return refuse(c, *error);
      }
      if (options.role == Role::Listener) {
        const auto proof = c->handshake->proof();
        c->handshake_out.emplace_back(proof.begin(), proof.end());
      }
      activate(c);
    });
  }

  void close(ConnectionPtr c) {  // by value: callers pass `active`, which this may reset
    if (c->closed) return;
    c->closed = true;
    std::error_code ignored;
    c->socket.shutdown(tcp::socket::shutdown_both, ignored);
    c->socket.close(ignored);
    c->handshake_timer.cancel();
    connections.erase(c);
    // The keys go with the connection, not when the last handler holding it is done.
    c->handshake.reset();
    c->sealer.reset();
    c->opener.reset();
  }

  // `definite`: the peer said something unacceptable (wrong key, not our protocol): status
  // Refused. Otherwise (timeout, closed) the remote is just not there: status stays Lost or
  // Connecting, with this reason.
  // Handshake bytes still queued (a listener's decoy proof) go out before the socket closes.
  void refuse(ConnectionPtr c, const std::string& reason, bool definite = true) {
    if (c->closed || c->refused) return;
    // While a lost session is being rebuilt, attempts that time out or are closed are expected
    // (the link is still down): counted, and told once in the line that says it is back.
    if (!definite && ever_connected && !active) {
      ++attempts_failed_while_lost;
      last_failed_attempt = reason;
    } else {
      log_limited("refused", [&] { return "connection with " + c->peer + " refused: " + reason; });
    }
    c->refused = true;
    if (c->handshake_out.empty() && !c->writing)
      close(c);
    else
      pump(c);
    count([](NetCounters& k) { ++k.handshakes_refused; });
    if (!active) {
      ConnectionState state = ConnectionState::Refused;
      if (!definite) {
        std::lock_guard lock(mutex);
        state = status.state == ConnectionState::Lost ? ConnectionState::Lost : ConnectionState::Connecting;
      }
      set_status(state, reason, c->peer);
    }
    if (options.role == Role::Connector && !active) schedule_connect();
  }

  void activate(const ConnectionPtr& c) {
    c->handshake_timer.cancel();
    TrafficKeys keys = c->handshake->keys();
    c->handshake->wipe();
    c->sealer.emplace(keys.send);
    c->opener.emplace(keys.receive, kMaxMessageSize);
    sodium_memzero(&keys, sizeof keys);
    c->body_in.reserve(kMaxRecordCiphertext);
    c->last_rx_us = monotonic_now_us();
    if (active) {
      log("a new authenticated connection from " + c->peer + " replaces the one with " + active->peer);
      close(active);
    }
    active = c;
    peer_address_key = c->address_key;
    backoff_attempt = 0;
    count([&](NetCounters& k) {
      ++k.handshakes_ok;
      if (ever_connected) ++k.reconnects;
    });
    uint64_t lost_since_us = 0;
    {
      std::lock_guard lock(mutex);
      if (status.state == ConnectionState::Lost) lost_since_us = status.since_us;
    }
    if (ever_connected && lost_since_us) {
      std::string line = "session re-established with " + c->peer + " after " +
                         std::to_string((monotonic_now_us() - lost_since_us) / 1000) + " ms";
      if (attempts_failed_while_lost)
        line += " (" + std::to_string(attempts_failed_while_lost) + " attempts failed meanwhile, the last: " +
                last_failed_attempt + ")";
      log(line);
    } else {
      log("session established with " + c->peer + " (" + role_name(options.role) + ")");
    }
    attempts_failed_while_lost = 0;
    ever_connected = true;
    set_status(ConnectionState::Connected, "", c->peer);
    read_record(c);
    pump(c);
  }

  void drop(ConnectionPtr c, const std::string& reason) {
    if (c->closed) return;
    const bool was_active = c == active;
    close(c);
    if (!was_active) return;
    active.reset();
    if (c->peer_ending) {
      log("the peer " + c->peer + " ended its session");
      count([](NetCounters& k) { ++k.sessions_ended_by_peer; });
      set_status(ConnectionState::Ended, "the peer ended its session", c->peer);
      return;  // its end is the session's: nothing to reconnect to
    } else {
      log("connection with " + c->peer + " lost: " + reason);
      count([](NetCounters& k) { ++k.connections_lost; });
      set_status(ConnectionState::Lost, reason, c->peer);
    }
    if (options.role == Role::Connector) schedule_connect();
  }

  // A record's length is not authenticated until its record is: it may size one record's buffer,
  // never more, and the bytes it promises count as life only once they authenticate.
  void read_record(const ConnectionPtr& c) {
    asio::async_read(c->socket, asio::buffer(c->header_in), [this, c](std::error_code e, size_t n) {
      count([&](NetCounters& k) { k.bytes_in += n; });
      if (c->closed) return;
      if (e) return drop(c, e == asio::error::eof ? "the peer closed the connection" : e.message());
      RecordHeader header;
      std::string reason;
      if (c->opener->check_header(c->header_in, &header, &reason) != RecordError::None) {
        reject(record_error_name(RecordError::Oversize), reason);
        return drop(c, reason);
      }
      c->body_in.resize(header.ciphertext_length);  // within the capacity reserved
      asio::async_read(c->socket, asio::buffer(c->body_in), [this, c](std::error_code e2, size_t n2) {
        count([&](NetCounters& k) { k.bytes_in += n2; });
        if (c->closed) return;
        if (e2) return drop(c, e2 == asio::error::eof ? "the peer closed the connection" : e2.message());
        on_record(c);
        if (!c->closed) read_record(c);
      });
    });
  }

  void on_record(const ConnectionPtr& c) {
    std::vector<uint8_t> plaintext;
    std::string reason;
    bool complete = false;
    // Every record error ends the connection: a forged or corrupted record, and an authentic one
    // out of sequence (TCP loses nothing: a gap means one was deleted on the way, perhaps a
    // touch event picked out by its size). The connector then builds a new one.
    const RecordError error = c->opener->open(c->header_in, c->body_in, &plaintext, &reason, &complete);
    if (error != RecordError::None) {
      // The reason first: a reader that sees the gap counted sees its reason too.
      reject(record_error_name(error), reason);
      if (error == RecordError::OutOfSequence) count([](NetCounters& k) { ++k.records_out_of_sequence; });
      return drop(c, reason);
    }
    c->last_rx_us = monotonic_now_us();
    if (!complete) return;
    DecodeError header_error;
    const auto header = decode_header(plaintext, &header_error);
    if (header && header->type == uint16_t(MessageType::Portrait)) {
      {
        std::lock_guard lock(mutex);
        if (portrait_pending) ++counters.stale_dropped_in[size_t(message_type_index(MessageType::Portrait))];
        portrait_pending = std::move(plaintext);
      }
      portrait_wake.notify_one();
      return;
    }
    decode_and_deliver(plaintext, c.get());
  }

  void decode_and_deliver(std::span<const uint8_t> plaintext, Connection* from = nullptr) {
    DecodeResult result = decode_message(plaintext, options.decode);
    if (!result.ok()) return reject(decode_error_kind_name(result.error.kind), result.error.message);
    if (const auto* heartbeat = std::get_if<HeartbeatMessage>(&*result.message); heartbeat && from)
      from->peer_ending = from->peer_ending || heartbeat->ending;
    deliver(std::move(*result.message));
  }

  void decode_portraits() {
    std::unique_lock lock(mutex);
    while (true) {
      portrait_wake.wait(lock, [this] { return portrait_stop || portrait_pending; });
      if (portrait_stop) return;
      std::vector<uint8_t> bytes = std::move(*portrait_pending);
      portrait_pending.reset();
      lock.unlock();
      decode_and_deliver(bytes);
      lock.lock();
    }
  }

  void deliver(Message message) {
    const int index = message_type_index(message_type(message));
    if (const auto* touch = std::get_if<TouchEventMessage>(&message)) {
      std::lock_guard lock(mutex);
      if (touch->sender_session != peer_touch_session) {  // the peer's run started again
        peer_touch_session = touch->sender_session;
        peer_touch_sequence = 0;
      }
      if (touch->sequence <= peer_touch_sequence) {  // sent again after a reconnect, already here
        ++counters.touch_duplicates_in;
        return;
      }
      peer_touch_sequence = touch->sequence;
    }
    if (const auto* heartbeat = std::get_if<HeartbeatMessage>(&message)) {
      std::lock_guard lock(mutex);
      if (heartbeat->touches_acked_session == touch_session)
        while (!out_touch.empty() && out_touch.front().first <= heartbeat->touches_acked_sequence) {
          out_touch.pop_front();
          ++counters.touches_acked;
        }
    }
    // The mailbox takes the message (moved: a 720p portrait is 18 MB of floats); the handler, if
    // any, gets a copy afterwards, so that a handler seeing a message can already take() it.
    std::optional<Message> for_handler;
    if (handler) for_handler = message;
    {
      std::lock_guard lock(mutex);
      ++counters.messages_in[size_t(index)];
      auto put = [&](auto& slot, auto& value) {
        if (slot) ++counters.stale_dropped_in[size_t(index)];
        slot = std::move(value);
      };
      std::visit(
          [&](auto& m) {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, EyeMessage>) put(in_eye, m);
            if constexpr (std::is_same_v<T, PortraitMessage>) put(in_portrait, m);
            if constexpr (std::is_same_v<T, SkeletonMessage>) put(in_skeleton, m);
            if constexpr (std::is_same_v<T, HeartbeatMessage>) put(in_heartbeat, m);
            // Signals and voice frames have no mailbox: the handler (the WebRTC link's, the site
            // sound's) takes each, in order.
            if constexpr (std::is_same_v<T, TouchEventMessage>) {
              if (in_touch.size() >= options.incoming_touch_capacity) {
                ++counters.stale_dropped_in[size_t(index)];
                in_touch.erase(in_touch.begin());
              }
              in_touch.push_back(m);
            }
          },
          message);
    }
    if (for_handler) handler(*for_handler);
  }

  // ---- writing (network thread) ----

  std::optional<Outgoing> next_outgoing(const Connection& c) {
    std::lock_guard lock(mutex);
    for (const auto& [sequence, bytes] : out_touch)
      if (sequence > c.touches_written) return Outgoing{MessageType::TouchEvent, bytes, sequence};
    if (!out_signal.empty()) {
      Outgoing o{MessageType::Signal, std::move(out_signal.front()), 0, false};
      out_signal.pop_front();
      return o;
    }
    if (out_heartbeat) {
      Outgoing o{MessageType::Heartbeat, std::move(*out_heartbeat), 0, goodbye_pending};
      out_heartbeat.reset();
      return o;
    }
    // Voice before the pictures: a frame is small and its listener hears a late one as a gap.
    if (!out_voice.empty()) {
      Outgoing o{MessageType::Voice, std::move(out_voice.front()), 0, false};
      out_voice.pop_front();
      return o;
    }
    for (auto [slot, type] : {std::pair{&out_eye, MessageType::Eye}, {&out_skeleton, MessageType::Skeleton},
                              {&out_portrait, MessageType::Portrait}})
      if (*slot) {
        Outgoing o{type, std::move(**slot), 0, false};
        slot->reset();
        return o;
      }
    return std::nullopt;
  }

  void pump(const ConnectionPtr& c) {
    if (c->writing || c->closed) return;
    std::optional<MessageType> type;
    uint64_t touch_sequence = 0;
    bool goodbye = false;
    if (!c->handshake_out.empty()) {
      c->writing_buffer = std::move(c->handshake_out.front());
      c->handshake_out.pop_front();
    } else if (c->refused) {
      return close(c);
    } else if (c == active) {
      auto next = next_outgoing(*c);
      if (!next) return;
      type = next->type;
      touch_sequence = next->touch_sequence;
      goodbye = next->goodbye;
      c->writing_buffer = c->sealer->seal_message(next->bytes);
    } else {
      return;
    }
    c->writing = true;
    asio::async_write(c->socket, asio::buffer(c->writing_buffer), [this, c, type, touch_sequence, goodbye](std::error_code e, size_t n) {
      c->writing = false;
      {
        std::lock_guard lock(mutex);
        counters.bytes_out += n;
        if (!e && type) ++counters.messages_out[size_t(message_type_index(*type))];
        if (!e && touch_sequence) {
          c->touches_written = touch_sequence;
          if (touch_sequence <= touches_written_any)
            ++counters.touches_resent;  // written on an earlier connection, not acknowledged
          else
            touches_written_any = touch_sequence;
        }
      }
      if (goodbye) return close_all();
      if (c->closed) return;
      if (e && c->refused) return close(c);
      if (e) return c == active ? drop(c, "write failed: " + e.message()) : refuse(c, "write failed: " + e.message(), false);
      pump(c);
    });
  }

  void wake() {
    asio::post(io, [this] {
      if (active && !closing) pump(active);
    });
  }

  // ---- connecting, accepting, ticking (network thread) ----

  void schedule_connect() {
    if (closing) return;
    const auto delay = std::min<std::chrono::milliseconds>(options.reconnect_max,
                                                           options.reconnect_min * (1 << std::min(backoff_attempt, 16)));
    ++backoff_attempt;
    connect_timer.expires_after(delay);
    connect_timer.async_wait([this](std::error_code e) {
      if (!e && !closing) connect();
    });
  }

  // A peer that stays unreachable fails the same way on every try: the log says each reason
  // once, and the status keeps it for the site's final message.
  void note_connect_failure(const std::string& reason) {
    std::lock_guard lock(mutex);
    if (status.reason != reason) options.log("[" + options.name + "] " + reason);
    if (status.state != ConnectionState::Connected) status.reason = reason;
  }

  void connect() {
    {
      std::lock_guard lock(mutex);
      if (status.state == ConnectionState::Idle) {
        status.state = ConnectionState::Connecting;
        status.since_us = monotonic_now_us();
      }
    }
    auto c = std::make_shared<Connection>(io);
    connections.insert(c);  // so that stop() closes it while it is still connecting
    std::error_code ec;
    tcp::resolver resolver(io);
    const auto endpoints = resolver.resolve(options.host, std::to_string(options.port), ec);
    if (ec) {
      close(c);
      note_connect_failure("cannot resolve " + options.host + ": " + ec.message());
      return schedule_connect();
    }
    asio::async_connect(c->socket, endpoints, [this, c](std::error_code e, const tcp::endpoint&) {
      if (closing || c->closed) return;
      if (e) {
        close(c);
        note_connect_failure("connect to " + options.host + ":" + std::to_string(options.port) + " failed: " + e.message());
        return schedule_connect();
      }
      begin(c);
    });
  }

  // A connection from a network over its rate is closed before anything is read or allocated.
  bool admit(const tcp::endpoint& from, const std::string& key, uint64_t now_us) {
    if (key == peer_address_key || connection_rate.admit(prefix_key(key), now_us)) return true;
    count([](NetCounters& k) { ++k.connections_shed; });
    log_limited("shed", [&] {
      return "connections from " + from.address().to_string() + " closed unread: more than " +
             std::to_string(kNewConnectionsPerSecondPerAddress) + " new ones a second from its network (" +
             (from.address().is_v4() ? "/24" : "/64") + ")";
    });
    return false;
  }

  // Waits until a connection is there, then takes every one the backlog holds. While a flood is
  // being shed it waits a little between rounds, so that one wake-up sheds many connections
  // instead of each costing the network thread a sleep and a wake; a real peer waits that little.
  // accept4 itself, not Asio's accept: a shed connection then costs two system calls (accept and
  // close), not five (Asio also asks for the address and registers and unregisters the socket).
  void accept() {
    acceptor.async_wait(tcp::acceptor::wait_read, [this](std::error_code e) {
      if (closing) return;
      if (e) return accept_failed(e);
      bool shed = false;
      for (int taken = 0; taken < kMaxAcceptsPerRound; ++taken) {
        tcp::endpoint from;
        socklen_t length = socklen_t(from.capacity());
        const int fd = ::accept4(acceptor.native_handle(), from.data(), &length, SOCK_CLOEXEC);
        if (fd < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR || errno == ECONNABORTED)) {
          if (errno == EINTR || errno == ECONNABORTED) continue;
          break;
        }
        if (fd < 0) return accept_failed(std::error_code(errno, std::generic_category()));
        accept_backoff = std::chrono::milliseconds(0);
        from.resize(length);
        const std::string key = address_key(from.address());
        const uint64_t now_us = monotonic_now_us();
        if (!admit(from, key, now_us) || !make_room_for_hello(key, now_us)) {
          ::close(fd);
          shed = true;
          continue;
        }
        auto c = std::make_shared<Connection>(io);
        c->opened_us = now_us;
        std::error_code assign_error;
        c->socket.assign(from.protocol(), fd, assign_error);
        if (assign_error) {
          ::close(fd);
          log_limited("accept", "an accepted connection could not be used: " + assign_error.message());
          continue;
        }
        begin(c);
      }
      if (!shed) return accept();
      // Asio's reactor watches the listening socket edge-triggered even with no wait pending, so
      // every connection of the flood would still wake the thread during the pause: the socket
      // leaves the reactor until the pause is over.
      std::error_code release_error;
      const tcp::endpoint local = acceptor.local_endpoint(release_error);
      if (release_error) return accept();
      listener_fd_paused = acceptor.release(release_error);
      if (release_error) return accept();
      accept_timer.expires_after(kShedPause);
      accept_timer.async_wait([this, protocol = local.protocol()](std::error_code timer_error) {
        if (timer_error || closing) return;  // shut_down() closes the paused socket
        std::error_code assign_error;
        acceptor.assign(protocol, std::exchange(listener_fd_paused, -1), assign_error);
        if (assign_error) return log("cannot listen again after shedding a flood: " + assign_error.message());
        accept();
      });
    });
  }

  void accept_failed(std::error_code e) {
    count([](NetCounters& c) { ++c.accept_errors; });
    ++accept_errors_unlogged;
    const auto now = std::chrono::steady_clock::now();
    if (now - accept_error_logged >= std::chrono::seconds(1)) {
      log("accept failed: " + e.message() +
          (accept_errors_unlogged > 1 ? " (" + std::to_string(accept_errors_unlogged) + " times since the last report)" : ""));
      accept_errors_unlogged = 0;
      accept_error_logged = now;
    }
    accept_backoff = std::clamp(accept_backoff * 2, std::chrono::milliseconds(10), std::chrono::milliseconds(1000));
    accept_timer.expires_after(accept_backoff);
    accept_timer.async_wait([this](std::error_code timer_error) {
      if (!timer_error && !closing) accept();
    });
  }

  HeartbeatMessage next_heartbeat() {
    HeartbeatMessage heartbeat{monotonic_now_us(), ++heartbeat_sequence};
    std::lock_guard lock(mutex);
    heartbeat.touches_acked_session = peer_touch_session;
    heartbeat.touches_acked_sequence = peer_touch_sequence;
    return heartbeat;
  }

  void tick() {
    tick_timer.expires_after(options.heartbeat_period);
    tick_timer.async_wait([this](std::error_code e) {
      if (e || closing) return;
      if (active) {
        const uint64_t now = monotonic_now_us();
        const uint64_t silent_us = now - active->last_rx_us;
        if (silent_us > uint64_t(options.lost_after.count()) * 1000) {
          drop(active, "no data from the peer for " + std::to_string(silent_us / 1000) + " ms");
        } else {
          auto bytes = encode_message(next_heartbeat());
          {
            std::lock_guard lock(mutex);
            out_heartbeat = std::move(bytes);
          }
          pump(active);
        }
      }
      tick();
    });
  }

  // With a connection up, a last heartbeat says goodbye first, so that the peer takes the close
  // for the session's end and not a loss; it waits for that write at most kGoodbyeWait.
  void shut_down() {
    closing = true;
    std::error_code ignored;
    acceptor.close(ignored);
    if (listener_fd_paused >= 0) ::close(std::exchange(listener_fd_paused, -1));
    connect_timer.cancel();
    tick_timer.cancel();
    accept_timer.cancel();
    if (active && !active->closed) {
      HeartbeatMessage goodbye = next_heartbeat();
      goodbye.ending = true;
      auto bytes = encode_message(goodbye);
      {
        std::lock_guard lock(mutex);
        out_heartbeat = std::move(bytes);
      }
      goodbye_pending = true;
      goodbye_timer.expires_after(kGoodbyeWait);
      goodbye_timer.async_wait([this](std::error_code) { close_all(); });
      pump(active);
      return;
    }
    close_all();
  }

  void close_all() {
    goodbye_pending = false;
    goodbye_timer.cancel();
    for (auto c : std::vector<ConnectionPtr>(connections.begin(), connections.end())) close(c);
    active.reset();
  }
};

Session::Session(SessionOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}

Session::~Session() { stop(); }

void Session::start() {
  Impl& s = *impl_;
  if (s.thread.joinable()) return;
  if (s.options.role == Role::Listener) {
    const tcp::endpoint endpoint(asio::ip::make_address(s.options.host), s.options.port);
    s.acceptor.open(endpoint.protocol());
    s.acceptor.set_option(tcp::acceptor::reuse_address(true));
    std::error_code ec;
    s.acceptor.bind(endpoint, ec);
    if (ec)
      throw std::runtime_error("cannot listen on " + s.options.host + ":" + std::to_string(s.options.port) + ": " + ec.message());
    s.acceptor.listen();
    s.acceptor.non_blocking(true);  // accept() drains the backlog until it would block
    s.bound_port = s.acceptor.local_endpoint().port();
    s.set_status(ConnectionState::Connecting, "waiting for the peer", "");
    s.log("listening on " + s.options.host + ":" + std::to_string(s.bound_port));
    s.accept();
  } else {
    asio::post(s.io, [&s] { s.connect(); });
  }
  s.tick();
  s.work.emplace(s.io.get_executor());
  {
    std::lock_guard lock(s.mutex);
    s.portrait_stop = false;
  }
  s.portrait_thread = std::thread([&s] { s.decode_portraits(); });
  s.thread = std::thread([&s] { s.io.run(); });
  // Named, so that its share of a core can be told apart (top -H, /proc/PID/task/*/comm).
  pthread_setname_np(s.thread.native_handle(), ("net " + s.options.name).substr(0, 15).c_str());
}

void Session::stop() {
  Impl& s = *impl_;
  if (!s.thread.joinable()) return;
  asio::post(s.io, [&s] { s.shut_down(); });
  s.work.reset();
  s.thread.join();
  {
    std::lock_guard lock(s.mutex);
    s.portrait_stop = true;
  }
  s.portrait_wake.notify_one();
  s.portrait_thread.join();
}

uint16_t Session::local_port() const { return impl_->bound_port; }

void Session::send(const Message& message) {
  if (const auto* touch = std::get_if<TouchEventMessage>(&message)) {
    Impl& s = *impl_;
    TouchEventMessage stamped = *touch;
    {
      std::lock_guard lock(s.mutex);
      stamped.sender_session = s.touch_session;
      stamped.sequence = s.next_touch_sequence++;
      if (s.out_touch.size() >= kMaxUnackedTouches) {
        s.out_touch.pop_front();
        ++s.counters.touches_unacked_dropped;
      }
      s.out_touch.emplace_back(stamped.sequence, encode_message(stamped));
    }
    s.wake();
    return;
  }
  send_encoded(message_type(message), encode_message(message, impl_->options.encode));
}

void Session::send_encoded(MessageType stream, std::vector<uint8_t> bytes) {
  Impl& s = *impl_;
  {
    std::lock_guard lock(s.mutex);
    auto replace = [&](std::optional<std::vector<uint8_t>>& slot) {
      if (slot) ++s.counters.stale_dropped_out[size_t(message_type_index(stream))];
      slot = std::move(bytes);
    };
    switch (stream) {
      case MessageType::Eye: replace(s.out_eye); break;
      case MessageType::Skeleton: replace(s.out_skeleton); break;
      case MessageType::Portrait: replace(s.out_portrait); break;
      case MessageType::Heartbeat: replace(s.out_heartbeat); break;
      case MessageType::Signal:
        if (s.out_signal.size() >= kMaxQueuedSignals) {
          s.out_signal.pop_front();
          ++s.counters.stale_dropped_out[size_t(message_type_index(stream))];
        }
        s.out_signal.push_back(std::move(bytes));
        break;
      case MessageType::Voice:
        if (s.out_voice.size() >= s.options.outgoing_voice_capacity) {
          ++s.counters.stale_dropped_out[size_t(message_type_index(stream))];
          s.out_voice.pop_front();
        }
        s.out_voice.push_back(std::move(bytes));
        break;
      case MessageType::TouchEvent:  // as encoded: send() is what numbers a touch event
        s.out_touch.emplace_back(s.next_touch_sequence++, std::move(bytes));
        break;
    }
  }
  s.wake();
}

template <typename T>
static std::optional<T> take(std::mutex& mutex, std::optional<T>& slot) {
  std::lock_guard lock(mutex);
  std::optional<T> out = std::move(slot);
  slot.reset();
  return out;
}

std::optional<EyeMessage> Session::take_eye() { return take(impl_->mutex, impl_->in_eye); }
std::optional<PortraitMessage> Session::take_portrait() { return take(impl_->mutex, impl_->in_portrait); }
std::optional<SkeletonMessage> Session::take_skeleton() { return take(impl_->mutex, impl_->in_skeleton); }
std::optional<HeartbeatMessage> Session::take_heartbeat() { return take(impl_->mutex, impl_->in_heartbeat); }

std::vector<TouchEventMessage> Session::take_touch_events() {
  std::lock_guard lock(impl_->mutex);
  return std::exchange(impl_->in_touch, {});
}

void Session::set_handler(std::function<void(const Message&)> handler) { impl_->handler = std::move(handler); }

ConnectionStatus Session::status() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->status;
}

NetCounters Session::counters() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->counters;
}

}  // namespace rt::net
