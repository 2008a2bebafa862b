#include "support/fake_leap_service.h"

#include <sys/socket.h>

namespace rt::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

FakeLeapService::FakeLeapService(uint16_t port, Script script) : acceptor_(io_) {
  const tcp::endpoint endpoint(asio::ip::make_address("127.0.0.1"), port);
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen();
  port_ = acceptor_.local_endpoint().port();
  thread_ = std::thread([this, script = std::move(script)] {
    while (!stopping_) {
      beast::error_code ec;
      tcp::socket socket(io_);
      acceptor_.accept(socket, ec);
      if (ec || stopping_) return;
      {
        std::lock_guard lock(serving_mutex_);
        if (stopping_) return;  // the destructor has looked for a connection to cut already
        serving_fd_ = socket.native_handle();
      }
      LeapSocket ws(std::move(socket));
      try {
        ws.accept();
        script(ws);
        ws.close(websocket::close_code::normal);
      } catch (const beast::system_error&) {
        // The client went away: wait for the next one.
      }
      {
        std::lock_guard lock(serving_mutex_);  // before the socket closes: its number may be reused
        serving_fd_ = -1;
      }
      ++served_;
    }
  });
}

FakeLeapService::~FakeLeapService() {
  {
    std::lock_guard lock(serving_mutex_);
    stopping_ = true;
    // Unblocks a script reading or writing: the connection fails under it, as when a client goes.
    if (serving_fd_ >= 0) ::shutdown(serving_fd_, SHUT_RDWR);
  }
  // Unblocks accept() with a connection to ourselves, then closes the port.
  beast::error_code ec;
  tcp::socket poke(io_);
  poke.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port_), ec);
  thread_.join();
  acceptor_.close(ec);
}

void greet(LeapSocket& ws, std::vector<std::string>* requests) {
  send_text(ws, R"({"version": 6, "serviceVersion": "fake-4.1.0"})");
  for (int i = 0; i < 2; ++i) {
    beast::flat_buffer buffer;
    ws.read(buffer);
    if (requests) requests->push_back(beast::buffers_to_string(buffer.data()));
  }
}

void hold(LeapSocket& ws) {
  for (;;) {
    beast::flat_buffer buffer;
    ws.read(buffer);  // throws once the client closes or the connection is cut
  }
}

void send_text(LeapSocket& ws, const std::string& text) {
  ws.text(true);
  ws.write(asio::buffer(text));
}

}  // namespace rt::test
