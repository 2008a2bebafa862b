#include "tracker/leap_service.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <cctype>
#include <stdexcept>

#include "config/json.h"
#include "sim/leap_json.h"
#include "time/monotonic_clock.h"

namespace rt::devices {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

const char* leap_state_name(LeapState state) {
  switch (state) {
    case LeapState::Connecting: return "connecting";
    case LeapState::Connected: return "connected";
    case LeapState::Lost: return "lost";
  }
  return "?";
}

std::optional<double> LeapServiceStatus::frames_per_second() const {
  if (frames < 2 || last_frame_us <= first_frame_us) return std::nullopt;
  return double(frames - 1) / (double(last_frame_us - first_frame_us) * 1e-6);
}

nlohmann::json LeapServiceStatus::to_json() const {
  const std::optional<double> rate = frames_per_second();
  return {{"state", leap_state_name(state)},
          {"frames_per_second", rate ? nlohmann::json(*rate) : nlohmann::json()},
          {"connections", connections},
          {"frames", frames},
          {"frames_with_hands", frames_with_hands},
          {"messages_refused", {{"malformed", messages_malformed}, {"oversized", messages_oversized}}},
          {"messages_other", messages_other},
          {"service_version", service_version},
          {"last_error", last_error}};
}

// One connection attempt and its life: resolve, connect, handshake, the two requests, then a read
// loop until an error ends it. Runs on the client thread's io_context only.
class LeapServiceTracker::Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(asio::io_context& io, LeapServiceTracker& owner) : owner_(owner), resolver_(io), ws_(io) {}

  void start() {
    resolver_.async_resolve(owner_.url_.host, owner_.url_.port,
                            [self = shared_from_this()](beast::error_code ec, tcp::resolver::results_type results) {
                              if (ec) return self->fail("cannot resolve", ec);
                              self->connect(results);
                            });
  }

 private:
  void connect(const tcp::resolver::results_type& results) {
    beast::get_lowest_layer(ws_).expires_after(owner_.options_.connect_timeout);
    beast::get_lowest_layer(ws_).async_connect(results, [self = shared_from_this()](beast::error_code ec, const tcp::endpoint&) {
      if (ec) return self->fail("cannot connect", ec);
      self->handshake();
    });
  }

  void handshake() {
    beast::get_lowest_layer(ws_).expires_never();
    websocket::stream_base::timeout timeouts{};
    timeouts.handshake_timeout = owner_.options_.connect_timeout;
    timeouts.idle_timeout = websocket::stream_base::none();
    timeouts.keep_alive_pings = false;
    ws_.set_option(timeouts);
    ws_.read_message_max(owner_.options_.max_message_bytes);
    ws_.async_handshake(owner_.url_.host + ":" + owner_.url_.port, owner_.url_.path,
                        [self = shared_from_this()](beast::error_code ec) {
                          if (ec) return self->fail("WebSocket handshake failed", ec);
                          {
                            std::lock_guard lock(self->owner_.mutex_);
                            self->owner_.status_.state = LeapState::Connected;
                            ++self->owner_.status_.connections;
                          }
                          self->owner_.changed_.notify_all();
                          // Frames while another application has the focus, too: a site runs unattended.
                          self->write(R"({"background": true})", [self] { self->write(R"({"focused": true})", [self] { self->read(); }); });
                        });
  }

  template <typename Next>
  void write(const char* text, Next next) {
    outgoing_ = text;
    ws_.text(true);
    ws_.async_write(asio::buffer(outgoing_), [self = shared_from_this(), next](beast::error_code ec, size_t) {
      if (ec) return self->fail("cannot write to the service", ec);
      next();
    });
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec == websocket::error::message_too_big) {
        std::lock_guard lock(self->owner_.mutex_);
        ++self->owner_.status_.messages_oversized;
      }
      if (ec) return self->fail("the connection ended", ec);
      self->owner_.handle_message(beast::buffers_to_string(self->buffer_.data()));
      self->buffer_.consume(self->buffer_.size());
      self->read();
    });
  }

  void fail(const char* what, const beast::error_code& ec) {
    owner_.set_error(std::string(what) + ": " + ec.message());
  }

  LeapServiceTracker& owner_;
  tcp::resolver resolver_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  std::string outgoing_;
};

LeapServiceTracker::LeapServiceTracker(Options options) : options_(std::move(options)), url_(parse_leap_url(options_.url)) {
  thread_ = std::thread([this] { run(); });
}

LeapServiceTracker::~LeapServiceTracker() {
  stopping_ = true;
  {
    std::lock_guard lock(mutex_);
    if (io_) std::static_pointer_cast<asio::io_context>(io_)->stop();
  }
  changed_.notify_all();
  thread_.join();
}

void LeapServiceTracker::run() {
  while (!stopping_) {
    auto io = std::make_shared<asio::io_context>();
    {
      std::lock_guard lock(mutex_);
      io_ = io;
    }
    if (stopping_) break;  // the destructor may have looked for io_ just before it was set
    std::make_shared<Connection>(*io, *this)->start();
    io->run();
    std::unique_lock lock(mutex_);
    io_.reset();
    if (status_.state == LeapState::Connected) status_.state = LeapState::Lost;
    changed_.notify_all();
    // A service that restarts takes a moment to listen again; do not spin on refusals meanwhile.
    changed_.wait_for(lock, options_.reconnect_delay, [this] { return stopping_.load(); });
  }
}

void LeapServiceTracker::set_error(const std::string& error) {
  {
    std::lock_guard lock(mutex_);
    status_.last_error = error;
  }
  changed_.notify_all();
}

void LeapServiceTracker::handle_message(const std::string& text) {
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  std::lock_guard lock(mutex_);
  if (json.is_discarded()) {
    ++status_.messages_malformed;
    status_.last_error = "a message that is not JSON (" + std::to_string(text.size()) + " bytes)";
    return;
  }
  // The service's greeting ({"version": 6, "serviceVersion": ...}) and its events are not frames.
  if (!json.is_object() || (!json.contains("hands") && !json.contains("pointables"))) {
    ++status_.messages_other;
    if (json.is_object() && json.contains("serviceVersion") && json["serviceVersion"].is_string())
      status_.service_version = json["serviceVersion"].get<std::string>();
    return;
  }
  try {
    sim::TrackerFrame frame = sim::frame_from_leap_json(json);
    ++status_.frames;
    if (!frame.hands.empty()) ++status_.frames_with_hands;
    const uint64_t now = monotonic_now_us();
    if (status_.frames == 1) status_.first_frame_us = now;
    status_.last_frame_us = now;
    newest_ = Received{std::move(frame), now, status_.frames};
  } catch (const config::JsonError& error) {
    ++status_.messages_malformed;
    status_.last_error = std::string("a frame refused: ") + error.what();
  }
}

void LeapServiceTracker::wait_connected(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (changed_.wait_for(lock, timeout, [this] { return status_.connections > 0; })) return;
  throw std::runtime_error("no Leap service answers at " + url_.text() + " within " + std::to_string(timeout.count()) +
                           " ms" + (status_.last_error.empty() ? std::string() : ": " + status_.last_error));
}

std::optional<LeapServiceTracker::Received> LeapServiceTracker::newest() const {
  std::lock_guard lock(mutex_);
  return newest_;
}

LeapServiceStatus LeapServiceTracker::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

}  // namespace rt::devices
