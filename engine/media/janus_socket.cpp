#include "media/janus_socket.h"

#include <gst/gst.h>
#include <openssl/ssl.h>
#include <openssl/x509_vfy.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <algorithm>
#include <deque>
#include <future>
#include <optional>
#include <stdexcept>
#include <thread>
#include <type_traits>

namespace rt::media {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

JanusUrl parse_janus_url(const std::string& url) {
  constexpr size_t kMaxJanusUrlBytes = 1024;
  const auto refuse = [&](const std::string& why) {
    const std::string shown = url.size() > 120 ? url.substr(0, 120) + "..." : url;
    return std::invalid_argument("--janus '" + shown + "': " + why + " (expected ws://HOST:PORT or wss://HOST:PORT)");
  };
  if (url.empty()) throw refuse("empty");
  if (url.size() > kMaxJanusUrlBytes) throw refuse("longer than " + std::to_string(kMaxJanusUrlBytes) + " bytes");
  if (std::any_of(url.begin(), url.end(), [](char c) { return c <= ' ' || c == 0x7f; }))
    throw refuse("a space or control character in it");
  if (!gst_is_initialized()) gst_init(nullptr, nullptr);
  std::unique_ptr<GstUri, decltype(&gst_uri_unref)> uri(gst_uri_from_string(url.c_str()), &gst_uri_unref);
  if (!uri || !gst_uri_get_scheme(uri.get())) throw refuse("not a URL");
  std::string scheme = gst_uri_get_scheme(uri.get());
  std::transform(scheme.begin(), scheme.end(), scheme.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (scheme != "ws" && scheme != "wss") throw refuse("the scheme '" + scheme + "'");
  JanusUrl out;
  out.tls = scheme == "wss";
  if (const char* host = gst_uri_get_host(uri.get())) out.host = host;
  if (out.host.empty()) throw refuse("no host");
  const unsigned port = gst_uri_get_port(uri.get());
  const size_t host_end = url.find(out.host) + out.host.size();
  if (port == GST_URI_NO_PORT && host_end < url.size() && url[host_end] == ':') throw refuse("a port that is not a number from 1 to 65535");
  if (port != GST_URI_NO_PORT && (port == 0 || port > 65535)) throw refuse("port " + std::to_string(port) + " is not from 1 to 65535");
  // Janus's own defaults for its plain and its secure WebSocket.
  out.port = std::to_string(port != GST_URI_NO_PORT ? port : out.tls ? 8989 : 8188);
  const gchar* path = gst_uri_get_path(uri.get());
  out.path = path && *path ? path : "/";
  if (gst_uri_get_query_table(uri.get()) || gst_uri_get_fragment(uri.get())) throw refuse("a query or fragment");
  return out;
}

class JanusSocket::Connection {
 public:
  virtual ~Connection() = default;
  virtual std::string open(std::chrono::milliseconds timeout) = 0;
  virtual void send(std::string text) = 0;
};

namespace {

template <bool kTls>
class JanusConnection final : public JanusSocket::Connection {
  using Layer = std::conditional_t<kTls, beast::ssl_stream<beast::tcp_stream>, beast::tcp_stream>;

 public:
  JanusConnection(JanusUrl url, std::string ca_file, size_t max_bytes, JanusSocketEvents events)
      : url_(std::move(url)), ca_file_(std::move(ca_file)), max_bytes_(max_bytes), events_(std::move(events)), resolver_(io_) {
    if constexpr (kTls)
      ws_.emplace(io_, tls_);
    else
      ws_.emplace(io_);
  }
  ~JanusConnection() override {
    io_.stop();
    if (thread_.joinable()) thread_.join();
  }

  std::string open(std::chrono::milliseconds timeout) override {
    if constexpr (kTls)
      if (std::string why = trust(); !why.empty()) return why;
    auto done = std::make_shared<std::promise<std::string>>();
    std::future<std::string> result = done->get_future();
    resolver_.async_resolve(url_.host, url_.port, [this, done, timeout](beast::error_code ec, tcp::resolver::results_type found) {
      if (ec) return done->set_value("cannot resolve " + url_.host + ": " + ec.message());
      beast::get_lowest_layer(*ws_).expires_after(timeout);
      beast::get_lowest_layer(*ws_).async_connect(found, [this, done, timeout](beast::error_code ec, const tcp::endpoint&) {
        if (ec) return done->set_value("cannot connect to " + where() + ": " + ec.message());
        if constexpr (kTls) {
          ws_->next_layer().async_handshake(asio::ssl::stream_base::client, [this, done, timeout](beast::error_code ec) {
            if (ec) return done->set_value("no TLS with " + where() + ": " + ec.message() + why_untrusted());
            upgrade(done, timeout);
          });
        } else {
          upgrade(done, timeout);
        }
      });
    });
    thread_ = std::thread([this] { io_.run(); });
    if (result.wait_for(timeout + std::chrono::seconds(1)) != std::future_status::ready)
      return "no answer from " + where() + " within " + std::to_string(timeout.count()) + " ms";
    return result.get();
  }

  void send(std::string text) override {
    asio::post(io_, [this, text = std::move(text)]() mutable {
      outgoing_.push_back(std::move(text));
      if (outgoing_.size() == 1) write_next();
    });
  }

 private:
  std::string where() const { return url_.host + ":" + url_.port; }

  // The certificate must chain to a trusted authority and name the host (its DNS name or its
  // address, as the URL gives it).
  std::string trust() {
    beast::error_code ec;
    if (ca_file_.empty())
      tls_.set_default_verify_paths(ec);
    else
      tls_.load_verify_file(ca_file_, ec);
    if (ec) return ca_file_.empty() ? "the system's trusted authorities cannot be read: " + ec.message()
                                    : "--janus-ca " + ca_file_ + ": cannot be read as PEM certificates: " + ec.message();
    if constexpr (kTls) {
      ws_->next_layer().set_verify_mode(asio::ssl::verify_peer);
      // OpenSSL's own check of the name, so that a mismatch is reported as one. An address is no
      // server name: it is checked as an address, and SNI carries names only.
      SSL* ssl = ws_->next_layer().native_handle();
      beast::error_code not_an_address;
      asio::ip::make_address(url_.host, not_an_address);
      const bool named = not_an_address ? SSL_set1_host(ssl, url_.host.c_str()) == 1 && SSL_set_tlsext_host_name(ssl, url_.host.c_str()) == 1
                                        : X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(ssl), url_.host.c_str()) == 1;
      if (!named) return "cannot name " + url_.host + " in the TLS handshake";
    }
    return {};
  }

  std::string why_untrusted() {
    if constexpr (kTls) {
      const long result = SSL_get_verify_result(ws_->next_layer().native_handle());
      if (result != X509_V_OK)
        return std::string(" (its certificate: ") + X509_verify_cert_error_string(result) +
               (ca_file_.empty() ? "; a server with its own authority needs --janus-ca FILE)" : ", against --janus-ca " + ca_file_ + ")");
    }
    return {};
  }

  void upgrade(std::shared_ptr<std::promise<std::string>> done, std::chrono::milliseconds timeout) {
    beast::get_lowest_layer(*ws_).expires_never();
    websocket::stream_base::timeout timeouts{};
    timeouts.handshake_timeout = timeout;
    timeouts.idle_timeout = websocket::stream_base::none();
    timeouts.keep_alive_pings = false;
    ws_->set_option(timeouts);
    ws_->read_message_max(max_bytes_);
    // Janus answers only a client that names its protocol.
    ws_->set_option(websocket::stream_base::decorator(
        [](websocket::request_type& request) { request.set(beast::http::field::sec_websocket_protocol, "janus-protocol"); }));
    ws_->async_handshake(where(), url_.path, [this, done](beast::error_code ec) {
      if (ec) return done->set_value("no WebSocket handshake with Janus at " + where() + url_.path + ": " + ec.message());
      done->set_value({});
      read();
    });
  }

  void write_next() {
    ws_->async_write(asio::buffer(outgoing_.front()), [this](beast::error_code ec, size_t) {
      if (ec) return events_.closed("cannot write to Janus: " + ec.message());
      outgoing_.pop_front();
      if (!outgoing_.empty()) write_next();
    });
  }

  void read() {
    ws_->async_read(buffer_, [this](beast::error_code ec, size_t) {
      if (ec == websocket::error::message_too_big) return events_.closed("Janus sent a message over " + std::to_string(max_bytes_) + " bytes");
      if (ec) return events_.closed("the connection to Janus ended: " + ec.message());
      events_.message(beast::buffers_to_string(buffer_.data()));
      buffer_.consume(buffer_.size());
      read();
    });
  }

  JanusUrl url_;
  std::string ca_file_;
  size_t max_bytes_;
  JanusSocketEvents events_;
  asio::io_context io_;
  asio::ssl::context tls_{asio::ssl::context::tls_client};
  tcp::resolver resolver_;
  std::optional<websocket::stream<Layer>> ws_;
  beast::flat_buffer buffer_;
  std::deque<std::string> outgoing_;
  std::thread thread_;
};

}  // namespace

JanusSocket::JanusSocket(JanusUrl url, std::string ca_file, size_t max_message_bytes, JanusSocketEvents events) {
  if (url.tls)
    connection_ = std::make_unique<JanusConnection<true>>(std::move(url), std::move(ca_file), max_message_bytes, std::move(events));
  else
    connection_ = std::make_unique<JanusConnection<false>>(std::move(url), std::move(ca_file), max_message_bytes, std::move(events));
}

JanusSocket::~JanusSocket() = default;

std::string JanusSocket::open(std::chrono::milliseconds timeout) { return connection_->open(timeout); }

void JanusSocket::send(std::string text) { connection_->send(std::move(text)); }

}  // namespace rt::media
