#include "net/net_counters.h"

namespace rt::net {

nlohmann::json NetCounters::to_json() const {
  auto per_type = [](const std::array<uint64_t, kMessageTypeCount>& values) {
    nlohmann::json out = nlohmann::json::object();
    for (int i = 0; i < kMessageTypeCount; ++i)
      if (is_message_type(uint16_t(i + 1))) out[message_type_name(MessageType(i + 1))] = values[size_t(i)];
    return out;
  };
  return {{"bytes_in", bytes_in},
          {"bytes_out", bytes_out},
          {"messages_in", per_type(messages_in)},
          {"messages_out", per_type(messages_out)},
          {"stale_dropped_out", per_type(stale_dropped_out)},
          {"stale_dropped_in", per_type(stale_dropped_in)},
          {"rejected", rejected},
          {"rejected_by_reason", rejected_by_reason},
          {"last_rejection", last_rejection},
          {"records_out_of_sequence", records_out_of_sequence},
          {"handshakes_ok", handshakes_ok},
          {"handshakes_refused", handshakes_refused},
          {"handshakes_started", handshakes_started},
          {"hellos_not_authentic", hellos_not_authentic},
          {"hellos_replayed", hellos_replayed},
          {"connections_lost", connections_lost},
          {"sessions_ended_by_peer", sessions_ended_by_peer},
          {"reconnects", reconnects},
          {"accept_errors", accept_errors},
          {"handshakes_dropped_for_room", handshakes_dropped_for_room},
          {"connections_shed", connections_shed},
          {"connections_turned_away", connections_turned_away},
          {"touches_acked", touches_acked},
          {"touches_resent", touches_resent},
          {"touch_duplicates_in", touch_duplicates_in},
          {"touches_unacked_dropped", touches_unacked_dropped}};
}

}  // namespace rt::net
