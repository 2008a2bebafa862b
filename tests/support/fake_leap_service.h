#pragma once
// A fake Leap service on loopback for the live tracker's tests: accepts one WebSocket client at a
// time and runs a script with it (greet, send frames, misbehave), as the real service's protocol
// goes (DESIGN.md section 6). Stops, closing its port, when destroyed; a script still talking to
// a client (one that holds the connection, say) is cut off then.
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace rt::test {

using LeapSocket = boost::beast::websocket::stream<boost::asio::ip::tcp::socket>;

class FakeLeapService {
 public:
  using Script = std::function<void(LeapSocket&)>;
  // Port 0: any free one (port() tells which); another port is taken again at once after a stop.
  FakeLeapService(uint16_t port, Script script);
  ~FakeLeapService();
  FakeLeapService(const FakeLeapService&) = delete;
  FakeLeapService& operator=(const FakeLeapService&) = delete;
  uint16_t port() const { return port_; }
  int served() const { return served_; }

 private:
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  uint16_t port_ = 0;
  std::atomic<bool> stopping_{false};
  std::atomic<int> served_{0};
  std::mutex serving_mutex_;
  int serving_fd_ = -1;  // the connection the script has, for the destructor to cut
  std::thread thread_;
};

// The service's greeting ({"version": 6, "serviceVersion": "fake-4.1.0"}), then the client's two
// requests read (and kept in `requests` when given).
void greet(LeapSocket& ws, std::vector<std::string>* requests = nullptr);
void send_text(LeapSocket& ws, const std::string& text);
// Keeps the connection open, reading (and dropping) whatever the client sends, until the client
// closes it or the service stops: a client then has no reason to reconnect, so what it received
// is what the script sent, however slowly the test looks.
void hold(LeapSocket& ws);

}  // namespace rt::test
