#pragma once
// What a session has done, readable at any time as a struct and printable as JSON.
#include <array>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "net/messages.h"

namespace rt::net {

struct NetCounters {
  uint64_t bytes_in = 0, bytes_out = 0;  // on the wire: handshakes, record headers, tags, payloads
  std::array<uint64_t, kMessageTypeCount> messages_in{}, messages_out{};  // indexed by message_type_index
  // Newest-wins streams: an unsent message replaced by a newer one (outgoing), or a received one
  // replaced before the receiver took it (incoming).
  std::array<uint64_t, kMessageTypeCount> stale_dropped_out{}, stale_dropped_in{};
  uint64_t rejected = 0;                              // messages and records refused
  std::map<std::string, uint64_t> rejected_by_reason;  // decode_error_kind_name / record_error_name
  std::string last_rejection;                          // the log line of the latest one
  // Authentic records whose counter was not the next one (deleted, replayed or reordered on the
  // way; TCP itself loses nothing): each ended its connection. Also in rejected_by_reason.
  uint64_t records_out_of_sequence = 0;
  uint64_t handshakes_ok = 0, handshakes_refused = 0;
  // Handshake state made (an ephemeral key pair): a listener makes one only for a hello whose MAC
  // proved the key and whose timestamp was new. The hellos it refused for either, before making any.
  uint64_t handshakes_started = 0, hellos_not_authentic = 0, hellos_replayed = 0;
  uint64_t connections_lost = 0;  // an active connection that died (not a peer's announced end)
  uint64_t sessions_ended_by_peer = 0;  // the peer said it was ending its session, then closed
  uint64_t reconnects = 0;  // sessions established after the first
  uint64_t accept_errors = 0;  // the listener's accept failed (e.g. out of descriptors)
  uint64_t handshakes_dropped_for_room = 0;  // pending handshakes closed to make room for newer ones
  uint64_t connections_shed = 0;  // closed at accept, unread: their network opened too many too fast
  // Closed at accept, unread: the room for connections awaiting their hello was full of young ones.
  uint64_t connections_turned_away = 0;
  // Touch events are acknowledged (acked: by the peer): one not yet acknowledged goes again on
  // the next connection (resent), a copy that arrives twice is dropped (duplicates_in), and beyond the session's
  // room for unacknowledged ones the oldest is given up (unacked_dropped).
  uint64_t touches_acked = 0, touches_resent = 0, touch_duplicates_in = 0, touches_unacked_dropped = 0;

  nlohmann::json to_json() const;
};

}  // namespace rt::net
