#include "media/janus_room.h"

#include <algorithm>
#include <stdexcept>

namespace rt::media {

using nlohmann::json;

namespace {

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

JanusRoom::JanusRoom(JanusRoomOptions options) : options_(std::move(options)) {
  if (options_.room == 0) throw std::runtime_error("--room: a room number from 1 up");
  if (options_.pin.size() > 256) throw std::runtime_error("the room's secret is longer than 256 bytes");
  if (options_.display.empty() || options_.display.size() > 64) throw std::runtime_error("a site's name in the room: 1 to 64 bytes");
  socket_ = std::make_unique<JanusSocket>(parse_janus_url(options_.url), options_.ca_file, options_.max_message_bytes,
                                          JanusSocketEvents{[this](std::string text) { on_message(text); },
                                                            [this](const std::string& why) { on_closed(why); }});
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
