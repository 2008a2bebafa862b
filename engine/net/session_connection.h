#pragma once
// One TCP connection of a session (session.cpp): its socket, its handshake and its records, what
// it has read and is writing. Only the session's network thread touches it.
#include <asio.hpp>
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "net/secure_channel.h"

namespace rt::net::session_detail {

using asio::ip::tcp;

struct Connection {
  explicit Connection(asio::io_context& io) : socket(io), handshake_timer(io) {}
  tcp::socket socket;
  asio::steady_timer handshake_timer;
  std::unique_ptr<Handshake> handshake;
  std::optional<RecordSealer> sealer;
  std::optional<RecordOpener> opener;
  std::array<uint8_t, kHelloSize> hello_in{};
  std::array<uint8_t, kProofSize> proof_in{};
  std::array<uint8_t, kRecordHeaderSize> header_in{};
  std::vector<uint8_t> body_in;  // one record's, its capacity reserved once authenticated
  // Listener: the connector's hello carried a MAC of our key and a new timestamp. Until then the
  // connection has cost a socket and a read, nothing more.
  bool hello_authentic = false;
  std::deque<std::vector<uint8_t>> handshake_out;
  std::vector<uint8_t> writing_buffer;
  uint64_t touches_written = 0;  // the sequence of the last touch event written on this connection
  bool writing = false, closed = false;
  bool peer_ending = false;  // the peer's last heartbeat said it is ending its session
  // Refused, but a decoy proof is still being written: closed once it is out (or on the
  // handshake timer), so that the connector learns of the refusal as a wrong proof.
  bool refused = false;
  uint64_t last_rx_us = 0;
  uint64_t opened_us = 0;
  std::string peer, address;  // address: the peer's IP alone, for the per-address cap
  std::string address_key;    // the IP's bytes: the peer's last address is recognised by it
};
using ConnectionPtr = std::shared_ptr<Connection>;

}  // namespace rt::net::session_detail
