#include "media/janus_room.h"

#include <gst/gst.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <future>
#include <stdexcept>

namespace rt::media {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using nlohmann::json;

namespace {

constexpr size_t kMaxJanusUrlBytes = 1024;
constexpr const char* kPlugin = "janus.plugin.videoroom";
constexpr size_t kMaxOtherPublishers = 8;

std::string short_text(const std::string& text) { return text.size() > 120 ? text.substr(0, 120) + "..." : text; }

// A number Janus gave as an id: a positive integer (Janus's default, without string_ids).
std::optional<uint64_t> id_in(const json& object, const char* key) {
  if (!object.is_object()) return std::nullopt;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_unsigned() || it->get<uint64_t>() == 0) return std::nullopt;
  return it->get<uint64_t>();
}

// The plugin's words in an event or a success: plugindata.data, or null.
const json* plugin_data(const json& message) {
  const auto pd = message.find("plugindata");
  if (pd == message.end() || !pd->is_object()) return nullptr;
  const auto data = pd->find("data");
  return data != pd->end() && data->is_object() ? &*data : nullptr;
}

std::string error_of(const json& message) {
  if (const auto e = message.find("error"); e != message.end() && e->is_object())
    return e->value("reason", std::string("no reason given")) + " (code " + std::to_string(e->value("code", 0)) + ")";
  if (const json* data = plugin_data(message); data && data->contains("error"))
    return (*data)["error"].is_string() ? (*data)["error"].get<std::string>() + " (code " + std::to_string(data->value("error_code", 0)) + ")"
                                         : std::string("an error without a reason");
  return {};
}

}  // namespace

JanusUrl parse_janus_url(const std::string& url) {
  const auto refuse = [&](const std::string& why) {
    return std::invalid_argument("--janus '" + short_text(url) + "': " + why + " (expected ws://HOST:PORT)");
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
  if (scheme == "wss") throw refuse("wss:// (WebSocket over TLS) is not supported yet: put Janus behind ws:// on a network you trust");
  if (scheme != "ws") throw refuse("the scheme '" + scheme + "'");
  JanusUrl out;
  if (const char* host = gst_uri_get_host(uri.get())) out.host = host;
  if (out.host.empty()) throw refuse("no host");
  const unsigned port = gst_uri_get_port(uri.get());
  const size_t host_end = url.find(out.host) + out.host.size();
  if (port == GST_URI_NO_PORT && host_end < url.size() && url[host_end] == ':') throw refuse("a port that is not a number from 1 to 65535");
  if (port != GST_URI_NO_PORT && (port == 0 || port > 65535)) throw refuse("port " + std::to_string(port) + " is not from 1 to 65535");
  out.port = std::to_string(port == GST_URI_NO_PORT ? 8188 : port);
  const gchar* path = gst_uri_get_path(uri.get());
  out.path = path && *path ? path : "/";
  if (gst_uri_get_query_table(uri.get()) || gst_uri_get_fragment(uri.get())) throw refuse("a query or fragment");
  return out;
}

// The WebSocket, on a thread of its own: reads hand each message to the room, writes go out in
// the order they were asked for.
class JanusRoom::Socket {
 public:
  Socket(JanusRoom& owner, JanusUrl url, size_t max_bytes)
      : owner_(owner), url_(std::move(url)), max_bytes_(max_bytes), resolver_(io_), ws_(io_) {}
  ~Socket() {
    io_.stop();
    if (thread_.joinable()) thread_.join();
  }

  // Empty, or why the connection could not be made.
  std::string open(std::chrono::milliseconds timeout) {
    auto done = std::make_shared<std::promise<std::string>>();
    std::future<std::string> result = done->get_future();
    resolver_.async_resolve(url_.host, url_.port, [this, done, timeout](beast::error_code ec, tcp::resolver::results_type found) {
      if (ec) return done->set_value("cannot resolve " + url_.host + ": " + ec.message());
      beast::get_lowest_layer(ws_).expires_after(timeout);
      beast::get_lowest_layer(ws_).async_connect(found, [this, done, timeout](beast::error_code ec, const tcp::endpoint&) {
        if (ec) return done->set_value("cannot connect to " + url_.host + ":" + url_.port + ": " + ec.message());
        beast::get_lowest_layer(ws_).expires_never();
        websocket::stream_base::timeout timeouts{};
        timeouts.handshake_timeout = timeout;
        timeouts.idle_timeout = websocket::stream_base::none();
        timeouts.keep_alive_pings = false;
        ws_.set_option(timeouts);
        ws_.read_message_max(max_bytes_);
        // Janus answers only a client that names its protocol.
        ws_.set_option(websocket::stream_base::decorator(
            [](websocket::request_type& request) { request.set(beast::http::field::sec_websocket_protocol, "janus-protocol"); }));
        ws_.async_handshake(url_.host + ":" + url_.port, url_.path, [this, done](beast::error_code ec) {
          if (ec) return done->set_value("no WebSocket handshake with Janus at " + url_.host + ":" + url_.port + url_.path + ": " + ec.message());
          done->set_value({});
          read();
        });
      });
    });
    thread_ = std::thread([this] { io_.run(); });
    if (result.wait_for(timeout + std::chrono::seconds(1)) != std::future_status::ready)
      return "no answer from " + url_.host + ":" + url_.port + " within " + std::to_string(timeout.count()) + " ms";
    return result.get();
  }

  void send(std::string text) {
    asio::post(io_, [this, text = std::move(text)]() mutable {
      outgoing_.push_back(std::move(text));
      if (outgoing_.size() == 1) write_next();
    });
  }

 private:
  void write_next() {
    ws_.async_write(asio::buffer(outgoing_.front()), [this](beast::error_code ec, size_t) {
      if (ec) return owner_.on_closed("cannot write to Janus: " + ec.message());
      outgoing_.pop_front();
      if (!outgoing_.empty()) write_next();
    });
  }
  void read() {
    ws_.async_read(buffer_, [this](beast::error_code ec, size_t) {
      if (ec == websocket::error::message_too_big) return owner_.on_closed("Janus sent a message over " + std::to_string(max_bytes_) + " bytes");
      if (ec) return owner_.on_closed("the connection to Janus ended: " + ec.message());
      ws_.text(ws_.got_text());
      owner_.on_message(beast::buffers_to_string(buffer_.data()));
      buffer_.consume(buffer_.size());
      read();
    });
  }

  JanusRoom& owner_;
  JanusUrl url_;
  size_t max_bytes_;
  asio::io_context io_;
  tcp::resolver resolver_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  std::deque<std::string> outgoing_;
  std::thread thread_;
};

JanusRoom::JanusRoom(JanusRoomOptions options) : options_(std::move(options)) {
  if (options_.room == 0) throw std::runtime_error("--room: a room number from 1 up");
  if (options_.pin.size() > 256) throw std::runtime_error("the room's secret is longer than 256 bytes");
  if (options_.display.empty() || options_.display.size() > 64) throw std::runtime_error("a site's name in the room: 1 to 64 bytes");
  socket_ = std::make_unique<Socket>(*this, parse_janus_url(options_.url), options_.max_message_bytes);
  if (const std::string why = socket_->open(options_.timeout); !why.empty()) throw std::runtime_error("Janus: " + why);
  const json created = request({{"janus", "create"}}, "making a session");
  const json* data = created.contains("data") ? &created["data"] : nullptr;
  const std::optional<uint64_t> session = data ? id_in(*data, "id") : std::nullopt;
  if (!session) throw std::runtime_error("Janus answered 'create' without a session id");
  session_ = *session;
  publisher_handle_ = attach("attaching to the VideoRoom plugin");
  subscriber_handle_ = attach("attaching to the VideoRoom plugin");
  // The room, made if it is missing: two publishers, the codecs the call uses. Janus says 427
  // when it exists already, which is the second site's case. A Janus that makes rooms only for its
  // administrator refuses; the room may exist all the same, which join() finds out.
  json create = {{"request", "create"}, {"room", options_.room}, {"publishers", 2}, {"videocodec", "h264"},
                 {"audiocodec", "opus"}, {"is_private", true}, {"permanent", false}};
  if (!options_.pin.empty()) create["pin"] = options_.pin;
  const json made = plugin_request(Peer::Publisher, create, nullptr, nullptr);
  if (const json* d = plugin_data(made); d && d->contains("error_code") && d->value("error_code", 0) != 427)
    create_refused_ = error_of(made);
  // Last: a constructor that throws leaves no thread running.
  keepalive_thread_ = std::thread([this] {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      if (changed_.wait_for(lock, options_.keepalive, [this] { return stopping_; })) break;
      const std::string transaction = "k" + std::to_string(next_transaction_++);
      lock.unlock();
      socket_->send(json{{"janus", "keepalive"}, {"session_id", session_}, {"transaction", transaction}}.dump());
      lock.lock();
    }
  });
}

JanusRoom::~JanusRoom() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (keepalive_thread_.joinable()) keepalive_thread_.join();
  // The seat in the room is freed at once rather than when the session times out.
  if (session_ && socket_) socket_->send(json{{"janus", "destroy"}, {"session_id", session_}, {"transaction", "bye"}}.dump());
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  socket_.reset();
}

json JanusRoom::request(json message, const char* what) {
  std::unique_lock lock(mutex_);
  if (closed_) throw std::runtime_error(std::string("Janus, ") + what + ": " + closed_reason_);
  const std::string transaction = "t" + std::to_string(next_transaction_++);
  message["transaction"] = transaction;
  waiting_[transaction];
  lock.unlock();
  socket_->send(message.dump());
  lock.lock();
  const bool answered = changed_.wait_for(lock, options_.timeout, [&] { return waiting_[transaction].has_value() || closed_; });
  std::optional<json> answer = std::move(waiting_[transaction]);
  waiting_.erase(transaction);
  if (!answered || !answer) {
    const std::string why = closed_ ? closed_reason_ : "no answer within " + std::to_string(options_.timeout.count()) + " ms";
    throw std::runtime_error(std::string("Janus, ") + what + ": " + why);
  }
  if ((*answer)["janus"] == "error") throw std::runtime_error(std::string("Janus, ") + what + ": " + error_of(*answer));
  return std::move(*answer);
}

json JanusRoom::plugin_request(Peer peer, json body, const json* jsep, const char* what) {
  json message = {{"janus", "message"}, {"session_id", session_}, {"handle_id", handle_of(peer)}, {"body", std::move(body)}};
  if (jsep) message["jsep"] = *jsep;
  json answer = request(std::move(message), what ? what : "a VideoRoom request");
  if (what && !error_of(answer).empty()) throw std::runtime_error(std::string("Janus, ") + what + ": " + error_of(answer));
  return answer;
}

uint64_t JanusRoom::attach(const char* what) {
  const json attached = request({{"janus", "attach"}, {"session_id", session_}, {"plugin", kPlugin}}, what);
  const std::optional<uint64_t> id = attached.contains("data") ? id_in(attached["data"], "id") : std::nullopt;
  if (!id) throw std::runtime_error("Janus answered 'attach' without a handle id");
  return *id;
}

void JanusRoom::renew_subscriber_handle() {
  // Janus keeps a subscriber handle to a publisher that left, its peer connection idle; a join
  // on it would be refused as a second subscription. A new handle starts clean.
  const uint64_t old = subscriber_handle_;
  try {
    request({{"janus", "detach"}, {"session_id", session_}, {"handle_id", old}}, "detaching the last subscription");
  } catch (const std::runtime_error&) {
    // Janus may have dropped the handle with the publisher already; the new one is what matters.
  }
  subscriber_handle_ = attach("attaching a new subscription to the VideoRoom plugin");
}

uint64_t JanusRoom::join() {
  json body = {{"request", "join"}, {"ptype", "publisher"}, {"room", options_.room}, {"display", options_.display}};
  if (!options_.pin.empty()) body["pin"] = options_.pin;
  json joined;
  try {
    joined = plugin_request(Peer::Publisher, body, nullptr, "joining the room");
  } catch (const std::runtime_error& e) {
    if (create_refused_.empty()) throw;
    throw std::runtime_error(std::string(e.what()) + "; making room " + std::to_string(options_.room) +
                             " was refused: " + create_refused_);
  }
  const json* data = plugin_data(joined);
  const std::optional<uint64_t> id = data ? id_in(*data, "id") : std::nullopt;
  if (!id || data->value("videoroom", "") != "joined") throw std::runtime_error("Janus answered 'join' without this site's id");
  std::lock_guard lock(mutex_);
  my_id_ = *id;
  on_event(joined);
  return *id;
}

std::string JanusRoom::publish(const std::string& offer_sdp) {
  const json jsep = {{"type", "offer"}, {"sdp", offer_sdp}};
  const json answer = plugin_request(Peer::Publisher, {{"request", "publish"}}, &jsep, "publishing");
  const auto it = answer.find("jsep");
  if (it == answer.end() || !it->is_object() || it->value("type", "") != "answer" || !(*it)["sdp"].is_string())
    throw std::runtime_error("Janus answered 'publish' without an SDP answer");
  return (*it)["sdp"].get<std::string>();
}

std::optional<uint64_t> JanusRoom::wait_for_other(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (!changed_.wait_for(lock, timeout, [this] { return !others_.empty() || closed_; }) || others_.empty()) return std::nullopt;
  return *others_.begin();
}

std::string JanusRoom::subscribe(uint64_t feed) {
  json body = {{"request", "join"}, {"ptype", "subscriber"}, {"room", options_.room}, {"streams", json::array({{{"feed", feed}}})}};
  if (!options_.pin.empty()) body["pin"] = options_.pin;
  {
    std::lock_guard lock(mutex_);
    subscribed_feed_ = feed;
    other_left_ = false;
  }
  const json attached = plugin_request(Peer::Subscriber, body, nullptr, "subscribing to the other site");
  const auto it = attached.find("jsep");
  if (it == attached.end() || !it->is_object() || it->value("type", "") != "offer" || !(*it)["sdp"].is_string())
    throw std::runtime_error("Janus answered the subscription without an SDP offer");
  return (*it)["sdp"].get<std::string>();
}

void JanusRoom::start(const std::string& answer_sdp) {
  const json jsep = {{"type", "answer"}, {"sdp", answer_sdp}};
  plugin_request(Peer::Subscriber, {{"request", "start"}}, &jsep, "starting the subscription");
}

void JanusRoom::trickle(Peer peer, unsigned mline, const std::string& candidate) {
  json message = {{"janus", "trickle"}, {"session_id", session_}, {"handle_id", handle_of(peer)}};
  message["candidate"] = candidate.empty() ? json{{"completed", true}} : json{{"sdpMLineIndex", mline}, {"candidate", candidate}};
  {
    std::lock_guard lock(mutex_);
    message["transaction"] = "c" + std::to_string(next_transaction_++);
  }
  socket_->send(message.dump());
}

void JanusRoom::on_message(const std::string& text) {
  json message = json::parse(text, nullptr, false);
  if (message.is_discarded() || !message.is_object() || !message.contains("janus") || !message["janus"].is_string())
    return refuse("a message from Janus that is not a JSON object with a 'janus' kind: " + short_text(text));
  const std::string kind = message["janus"];
  if (kind == "ack") return;  // the real answer to an asynchronous request follows
  std::lock_guard lock(mutex_);
  if (const auto t = message.find("transaction"); t != message.end() && t->is_string()) {
    if (auto waiting = waiting_.find(*t); waiting != waiting_.end() && !waiting->second &&
                                          (kind == "success" || kind == "error" || kind == "event")) {
      waiting->second = std::move(message);
      changed_.notify_all();
      return;
    }
  }
  on_event(message);
}

// What Janus says unasked: who publishes in the room, who left, a peer connection's end.
void JanusRoom::on_event(const json& message) {
  const std::string kind = message.value("janus", "");
  if (kind == "hangup") {
    last_error_ = "Janus hung up a peer connection: " + message.value("reason", std::string("no reason given"));
  } else if (kind == "timeout") {
    closed_ = true;
    closed_reason_ = "Janus ended the session (no keepalive in time)";
  }
  const json* data = plugin_data(message);
  if (!data) return changed_.notify_all();
  if (const auto publishers = data->find("publishers"); publishers != data->end() && publishers->is_array())
    for (const json& p : *publishers) {
      const std::optional<uint64_t> id = id_in(p, "id");
      if (!id || *id == my_id_) continue;
      // The room holds two publishers: a server that names many more is not believed, nor kept.
      if (others_.size() >= kMaxOtherPublishers) {
        ++refused_;
        last_error_ = "Janus named more publishers in the room than it can hold";
        break;
      }
      others_.insert(*id);
    }
  for (const char* gone : {"unpublished", "leaving"})
    if (const std::optional<uint64_t> id = id_in(*data, gone)) {
      others_.erase(*id);
      if (*id == subscribed_feed_) other_left_ = true;
    }
  changed_.notify_all();
}

void JanusRoom::on_closed(const std::string& why) {
  std::lock_guard lock(mutex_);
  if (!closed_) closed_reason_ = why;
  closed_ = true;
  changed_.notify_all();
}

void JanusRoom::refuse(const std::string& why) {
  std::lock_guard lock(mutex_);
  ++refused_;
  last_error_ = why;
}

bool JanusRoom::other_left() const {
  std::lock_guard lock(mutex_);
  return other_left_;
}

bool JanusRoom::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

std::string JanusRoom::closed_reason() const {
  std::lock_guard lock(mutex_);
  return closed_reason_;
}

std::string JanusRoom::last_error() const {
  std::lock_guard lock(mutex_);
  return closed_ && last_error_.empty() ? closed_reason_ : last_error_;
}

uint64_t JanusRoom::messages_refused() const {
  std::lock_guard lock(mutex_);
  return refused_;
}

}  // namespace rt::media
