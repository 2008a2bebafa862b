#pragma once
// The WebSocket to a Janus server (Boost.Beast), plain (ws://) or over TLS (wss://), on a thread
// of its own: each message read goes to a callback, writes go out in the order they were asked
// for. A public Janus sits behind TLS; its certificate is checked against the system's trusted
// authorities, or against one file of them (`site --janus-ca FILE`) for a server with its own,
// and must name the URL's host: a server that cannot prove it is the one named is refused.
#include <chrono>
#include <functional>
#include <memory>
#include <string>

namespace rt::media {

struct JanusUrl {
  std::string host, port, path;
  bool tls = false;
};
// "ws://HOST[:PORT][/PATH]" (port 8188, Janus's, if left out) or "wss://..." (port 8989). Throws
// std::invalid_argument naming what is wrong.
JanusUrl parse_janus_url(const std::string& url);

struct JanusSocketEvents {
  std::function<void(std::string)> message;         // one whole message, as text
  std::function<void(const std::string&)> closed;  // why the connection ended
};

class JanusSocket {
 public:
  // `ca_file`: the authorities a wss:// server's certificate is checked against; empty for the
  // system's. Nothing connects until open().
  JanusSocket(JanusUrl url, std::string ca_file, size_t max_message_bytes, JanusSocketEvents events);
  ~JanusSocket();
  JanusSocket(const JanusSocket&) = delete;
  JanusSocket& operator=(const JanusSocket&) = delete;

  // Empty once connected, else why the connection could not be made (the name, the connection,
  // the certificate and why it was not trusted, the WebSocket's handshake).
  std::string open(std::chrono::milliseconds timeout);
  void send(std::string text);

  class Connection;

 private:
  std::unique_ptr<Connection> connection_;
};

}  // namespace rt::media
