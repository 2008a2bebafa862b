// Two sessions over loopback: all five message types both ways, the wrong key refused on both
// sides, garbage from a stranger, malformed messages from a peer that holds the key, newest-wins
// portraits, touch events never dropped, counters as JSON.
#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <asio.hpp>
#include <cstring>
#include <filesystem>
#include <set>

#include "net_test_messages.h"
#include "net_test_sessions.h"
#include "time/monotonic_clock.h"

using namespace rt;
using namespace rt::net;

namespace {

// How long a test waits for what must happen: far beyond what it takes on a 2-core CI runner
// shared with other tests, so that only what never happens fails a test, never a slow machine.
constexpr std::chrono::milliseconds kPatienceNetSession{20000};

bool eventually_net_session(const std::function<bool()>& done) { return test::eventually(done, kPatienceNetSession); }

// A session logs each kind of refusal, shed or accept error once a second at most: from `since`
// (before the session started) to now, that is at most one line more than the whole seconds
// between. A loaded machine stretches the span; it cannot fit more lines into it.
size_t most_lines_since(std::chrono::steady_clock::time_point since) {
  return 1 + size_t(std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count());
}

// The lines that session `name` logged with `text` in them.
size_t lines_with(test::LogLines& log, const std::string& name, const std::string& text) {
  std::lock_guard lock(log.mutex);
  size_t n = 0;
  for (const auto& line : log.lines) n += line.starts_with("[" + name + "] ") && line.find(text) != std::string::npos;
  return n;
}

struct Received {
  std::mutex mutex;
  std::vector<Message> messages;
  std::set<MessageType> types() {
    std::lock_guard lock(mutex);
    std::set<MessageType> out;
    for (const auto& m : messages) out.insert(message_type(m));
    return out;
  }
  size_t count(MessageType type) {
    std::lock_guard lock(mutex);
    size_t n = 0;
    for (const auto& m : messages) n += message_type(m) == type;
    return n;
  }
};

struct Link {
  test::LogLines log;
  SessionKey key = random_session_key();
  Session listener{test::test_session_options(Role::Listener, key, log, "B")};
  std::unique_ptr<Session> connector;
  explicit Link(std::optional<SessionKey> connector_key = std::nullopt) {
    listener.start();
    auto options = test::test_session_options(Role::Connector, connector_key.value_or(key), log, "A");
    options.port = listener.local_port();
    connector = std::make_unique<Session>(options);
  }
};

}  // namespace

TEST_CASE("parse_host_port") {
  CHECK(parse_host_port("127.0.0.1:7000") == std::pair<std::string, uint16_t>{"127.0.0.1", 7000});
  CHECK(parse_host_port("[::1]:9") == std::pair<std::string, uint16_t>{"::1", 9});
  CHECK_THROWS_WITH(parse_host_port("localhost"), Catch::Contains("not HOST:PORT"));
  CHECK_THROWS_WITH(parse_host_port("h:70000"), Catch::Contains("1..65535"));
  CHECK_THROWS_WITH(parse_host_port("h:x1"), Catch::Contains("not a number"));
}

TEST_CASE("a session delivers all five message types both ways") {
  Received at_listener, at_connector;  // first: the sessions' threads deliver into them until the link goes
  Link link;
  link.listener.set_handler([&](const Message& m) {
    std::lock_guard lock(at_listener.mutex);
    at_listener.messages.push_back(m);
  });
  link.connector->set_handler([&](const Message& m) {
    std::lock_guard lock(at_connector.mutex);
    at_connector.messages.push_back(m);
  });
  link.connector->start();
  REQUIRE(link.connector->wait_connected(kPatienceNetSession));
  REQUIRE(link.listener.wait_connected(kPatienceNetSession));
  CHECK(link.log.contains("session established"));

  const PortraitMessage portrait = test::test_portrait(33, 17, 5);
  for (Session* s : {&link.listener, link.connector.get()}) {
    s->send(EyeMessage{monotonic_now_us(), {0.01, 0.02, -0.65}, true});
    s->send(portrait);
    s->send(test::test_skeleton(monotonic_now_us()));
    s->send(TouchEventMessage{monotonic_now_us(), TouchEventMessage::Kind::Start, s == &link.listener ? uint8_t(1) : uint8_t(0)});
    s->send(SignalMessage{SignalMessage::Kind::Candidate, 1, "candidate:1 1 UDP 2015363327 127.0.0.1 40000 typ host"});
  }
  const std::set<MessageType> all = {MessageType::Eye, MessageType::Portrait, MessageType::Skeleton,
                                     MessageType::TouchEvent, MessageType::Heartbeat, MessageType::Signal};
  REQUIRE(eventually_net_session([&] { return at_listener.types() == all && at_connector.types() == all; }));

  // The mailboxes hold the same: the newest of each stream, touch events all.
  for (Session* s : {&link.listener, link.connector.get()}) {
    const auto eye = s->take_eye();
    REQUIRE(eye);
    CHECK(eye->eye == Eigen::Vector3d(0.01, 0.02, -0.65));
    const auto got = s->take_portrait();
    REQUIRE(got);
    CHECK(got->frame_index == 5);
    CHECK(std::memcmp(got->depth.texels.data(), portrait.depth.texels.data(), portrait.depth.texels.size() * 4) == 0);
    CHECK(s->take_skeleton()->hands.size() == 2);
    CHECK(s->take_heartbeat());
    const auto touches = s->take_touch_events();
    REQUIRE(touches.size() == 1);
    CHECK(touches[0].site == (s == &link.listener ? 0 : 1));
    CHECK_FALSE(s->take_portrait());  // taken
    const NetCounters c = s->counters();
    CHECK(c.rejected == 0);
    CHECK(c.handshakes_ok == 1);
    CHECK(c.messages_out[size_t(message_type_index(MessageType::Portrait))] == 1);
    CHECK(c.bytes_out > 1000);
    CHECK(c.bytes_in > 1000);
    const auto json = c.to_json();
    CHECK(json["messages_in"]["portrait"] == 1);
    CHECK(json["messages_in"]["touch"] == 1);
  }
}

TEST_CASE("a session that stops says goodbye: its peer counts the session's end, not a lost connection") {
  Link link;
  link.connector->start();
  REQUIRE(link.connector->wait_connected(kPatienceNetSession));
  REQUIRE(link.listener.wait_connected(kPatienceNetSession));
  link.connector->send(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  link.connector->stop();  // the touch still goes, before the goodbye
  REQUIRE(eventually_net_session([&] { return link.listener.status().state == ConnectionState::Ended; }));
  const NetCounters c = link.listener.counters();
  CHECK(c.sessions_ended_by_peer == 1);
  CHECK(c.connections_lost == 0);
  CHECK(link.listener.status().reason == "the peer ended its session");
  CHECK(link.listener.take_touch_events().size() == 1);
  CHECK(link.log.contains("ended its session"));
}

// (A link cut without a goodbye counts as lost: test_net_faults, "a disconnect in the middle".)
TEST_CASE("a listener that stops says goodbye to its connector too") {
  Link link;
  link.connector->start();
  REQUIRE(link.listener.wait_connected(kPatienceNetSession));
  REQUIRE(link.connector->wait_connected(kPatienceNetSession));
  link.listener.stop();
  REQUIRE(eventually_net_session([&] { return link.connector->status().state != ConnectionState::Connected; }));
  CHECK(link.connector->counters().sessions_ended_by_peer == 1);
  CHECK(link.connector->counters().connections_lost == 0);
  // The session is over: the connector does not try to reach a peer that said goodbye.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CHECK(link.connector->status().state == ConnectionState::Ended);
  CHECK(link.connector->counters().reconnects == 0);
  CHECK_FALSE(link.log.contains("connect to"));
}

TEST_CASE("a peer with the wrong key is refused on both sides and nothing is delivered") {
  Link link(random_session_key());
  link.listener.set_handler([](const Message&) { FAIL("a message passed a failed handshake"); });
  link.connector->start();
  link.connector->send(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  REQUIRE(eventually_net_session([&] {
    return link.connector->status().state == ConnectionState::Refused && link.listener.status().state == ConnectionState::Refused;
  }));
  // The connector tries again after each refusal: a few retries, each refused the same way.
  REQUIRE(eventually_net_session([&] {
    return link.connector->counters().handshakes_refused >= 3 && link.listener.counters().handshakes_refused >= 3;
  }));
  // The listener refuses the connector's hello (its MAC is of another key) before making any
  // handshake state, and closes without a word; the connector says what that means.
  CHECK_THAT(link.listener.status().reason, Catch::Contains("hello is not authenticated with our session key"));
  CHECK_THAT(link.connector->status().reason, Catch::Contains("closed the connection without a hello") &&
                                                 Catch::Contains("wrong session key"));
  CHECK(link.listener.counters().handshakes_started == 0);
  CHECK(link.listener.counters().hellos_not_authentic >= 3);
  for (Session* s : {&link.listener, link.connector.get()}) {
    const ConnectionStatus status = s->status();
    CHECK_FALSE(status.connected());
    const NetCounters c = s->counters();
    CHECK(c.handshakes_ok == 0);
    CHECK(c.handshakes_refused >= 1);
    for (auto n : c.messages_in) CHECK(n == 0);
  }
  CHECK(link.log.contains("[A] connection with"));
  CHECK(link.log.contains("[B] connection with"));
}

TEST_CASE("garbage from a stranger is refused while the real session goes on") {
  Link link;
  link.connector->start();
  REQUIRE(link.listener.wait_connected(kPatienceNetSession));
  asio::io_context io;
  asio::ip::tcp::socket stranger(io);
  stranger.connect({asio::ip::make_address("127.0.0.1"), link.listener.local_port()});
  std::vector<uint8_t> garbage(200);
  for (size_t i = 0; i < garbage.size(); ++i) garbage[i] = uint8_t(i * 37 + 11);
  asio::write(stranger, asio::buffer(garbage));
  REQUIRE(eventually_net_session([&] { return link.listener.counters().handshakes_refused == 1; }));
  CHECK(link.log.contains("bad hello magic"));
  CHECK(link.listener.status().connected());
  link.connector->send(EyeMessage{7, {0, 0, -1}, true});
  REQUIRE(eventually_net_session([&] { return link.listener.take_eye().has_value(); }));
}

TEST_CASE("malformed messages from a peer holding the key are rejected, counted, and the session goes on") {
  Link link;
  link.connector->start();
  REQUIRE(link.listener.wait_connected(kPatienceNetSession));
  const auto good = encode_message(TouchEventMessage{5, TouchEventMessage::Kind::End, 0, 1, 1});
  std::vector<std::vector<uint8_t>> bad;
  bad.push_back({1, 2, 3});                       // truncated
  bad.push_back(good), bad.back()[0] = 'x';       // bad magic
  bad.push_back(good), bad.back()[6] = 42;        // unknown type
  bad.push_back(good), bad.back().push_back(0);   // trailing bytes
  bad.push_back(encode_message(EyeMessage{1, {0, 0, 0}, true}));
  const double nan = std::nan("");
  std::memcpy(bad.back().data() + kHeaderSize + 8, &nan, 8);  // NaN eye
  for (auto& bytes : bad) link.connector->send_encoded(MessageType::TouchEvent, bytes);
  link.connector->send_encoded(MessageType::TouchEvent, good);
  REQUIRE(eventually_net_session([&] { return link.listener.counters().messages_in[size_t(message_type_index(MessageType::TouchEvent))] == 1; }));
  const NetCounters c = link.listener.counters();
  CHECK(c.rejected == 5);
  CHECK(c.rejected_by_reason.at("truncated") == 1);
  CHECK(c.rejected_by_reason.at("bad_magic") == 1);
  CHECK(c.rejected_by_reason.at("unknown_type") == 1);
  CHECK(c.rejected_by_reason.at("trailing_bytes") == 1);
  CHECK(c.rejected_by_reason.at("bad_value") == 1);
  CHECK(link.log.contains("rejected: eye: eye position is not finite"));
  CHECK(link.listener.status().connected());
  CHECK(link.listener.take_touch_events().size() == 1);
}

TEST_CASE("portraits: only the newest unsent one goes, only the newest received one is kept") {
  Link link;
  constexpr size_t kPortrait = size_t(MessageType::Portrait) - 1;
  std::mutex mutex;
  std::vector<uint64_t> delivered;
  link.listener.set_handler([&](const Message& m) {
    if (const auto* p = std::get_if<PortraitMessage>(&m)) {
      std::lock_guard lock(mutex);
      delivered.push_back(p->frame_index);
    }
  });
  auto last_delivered = [&] {
    std::lock_guard lock(mutex);
    return delivered.empty() ? uint64_t(-1) : delivered.back();
  };
  const PortraitMessage first = test::test_portrait(20, 10, 0);
  // Not connected yet: each newer portrait replaces the unsent one.
  for (uint64_t frame = 0; frame < 5; ++frame) {
    PortraitMessage p = first;
    p.frame_index = frame;
    link.connector->send(p);
  }
  // Touch events queue instead: all arrive, in order.
  for (uint64_t i = 0; i < 50; ++i) link.connector->send(TouchEventMessage{i, TouchEventMessage::Kind(i % 2), 0});
  CHECK(link.connector->counters().stale_dropped_out[kPortrait] == 4);
  link.connector->start();
  REQUIRE(eventually_net_session([&] { return last_delivered() == 4; }));
  CHECK(link.listener.counters().messages_in[kPortrait] == 1);
  // Connected: the receiver does not poll while more arrive; it then finds only the newest.
  for (uint64_t frame = 5; frame < 12; ++frame) {
    PortraitMessage p = first;
    p.frame_index = frame;
    link.connector->send(p);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  REQUIRE(eventually_net_session([&] { return last_delivered() == 11; }));
  const auto newest = link.listener.take_portrait();
  REQUIRE(newest);
  CHECK(newest->frame_index == 11);
  CHECK_FALSE(link.listener.take_portrait());
  const NetCounters in = link.listener.counters();
  CHECK(in.messages_in[kPortrait] == delivered.size());
  CHECK(in.stale_dropped_in[kPortrait] >= delivered.size() - 1);  // every delivered one but the newest, at least
  for (size_t i = 1; i < delivered.size(); ++i) CHECK(delivered[i] > delivered[i - 1]);
  REQUIRE(eventually_net_session([&] { return link.listener.counters().messages_in[size_t(message_type_index(MessageType::TouchEvent))] == 50; }));
  const auto touches = link.listener.take_touch_events();
  REQUIRE(touches.size() == 50);
  for (uint64_t i = 0; i < 50; ++i) CHECK(touches[i].timestamp_us == i);
}

TEST_CASE("a portrait of many records (each at most 64 KiB of it) arrives intact") {
  Link link;
  link.connector->start();
  REQUIRE(link.listener.wait_connected(kPatienceNetSession));
  const PortraitMessage portrait = test::test_portrait(640, 480, 77, 5);
  const auto bytes = encode_message(portrait);
  REQUIRE(bytes.size() > 256 * 1024);
  link.connector->send_encoded(MessageType::Portrait, bytes);
  std::optional<PortraitMessage> got;
  REQUIRE(eventually_net_session([&] { return (got = link.listener.take_portrait()).has_value(); }));
  CHECK(got->frame_index == 77);
  CHECK(std::memcmp(got->depth.texels.data(), portrait.depth.texels.data(), portrait.depth.texels.size() * 4) == 0);
  CHECK(link.listener.counters().bytes_in > bytes.size());
}

TEST_CASE("sending an invalid message throws on the sender's thread") {
  Link link;
  CHECK_THROWS_AS(link.connector->send(EyeMessage{1, {std::nan(""), 0, 0}, true}), std::invalid_argument);
}

TEST_CASE("out of descriptors, the listener backs off instead of spinning, and recovers") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  const auto started = std::chrono::steady_clock::now();
  Session listener(test::test_session_options(Role::Listener, key, log, "B"));
  listener.start();
  const uint16_t port = listener.local_port();

  // Leave a few descriptors, then fill them with connections the listener cannot accept: each
  // pending one makes accept() fail with EMFILE until a descriptor frees up.
  rlimit original{};
  REQUIRE(::getrlimit(RLIMIT_NOFILE, &original) == 0);
  size_t open_now = 0;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) open_now += entry.is_symlink() ? 1 : 0;
  rlimit tight = original;
  tight.rlim_cur = open_now + 8;
  REQUIRE(::setrlimit(RLIMIT_NOFILE, &tight) == 0);
  std::vector<int> clients;
  const sockaddr_in address = test::loopback_address(port);
  for (int i = 0; i < 40; ++i) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) break;
    clients.push_back(fd);
    ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  }
  REQUIRE(eventually_net_session([&] { return listener.counters().accept_errors > 0; }));

  rusage before{}, after{};
  ::getrusage(RUSAGE_SELF, &before);
  const auto start = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  ::getrusage(RUSAGE_SELF, &after);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  auto seconds = [](const timeval& t) { return double(t.tv_sec) + double(t.tv_usec) * 1e-6; };
  const double cpu_s = seconds(after.ru_utime) + seconds(after.ru_stime) - seconds(before.ru_utime) - seconds(before.ru_stime);
  const uint64_t errors = listener.counters().accept_errors;
  ::setrlimit(RLIMIT_NOFILE, &original);
  for (const int fd : clients) ::close(fd);
  INFO("CPU " << cpu_s << " s over " << wall_s << " s, " << errors << " accept errors");
  CHECK(cpu_s < 0.3 * wall_s);  // the whole test process, the listener's thread included
  CHECK(errors < 60);           // backed off: tens, not hundreds of thousands
  const size_t accept_lines = lines_with(log, "B", "accept failed");
  const size_t most_lines = most_lines_since(started);
  INFO(accept_lines << " lines of accept errors, " << most_lines << " at most at one a second");
  CHECK(accept_lines <= most_lines);

  // Descriptors back: a real peer gets in.
  auto options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = port;
  Session connector(options);
  connector.start();
  CHECK(connector.wait_connected(kPatienceNetSession));
  // (A retry already failing when the descriptors came back may still have counted one more.)
  const NetCounters counters = listener.counters();
  CHECK(counters.accept_errors >= errors);
  CHECK(counters.to_json()["accept_errors"] == counters.accept_errors);
}

namespace {
// A TCP connection to `to` from the loopback address `from` (any of 127.0.0.0/8).
int connect_from_net_session(const sockaddr_in& to, const std::string& from) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  REQUIRE(fd >= 0);
  sockaddr_in source{};
  source.sin_family = AF_INET;
  REQUIRE(::inet_pton(AF_INET, from.c_str(), &source.sin_addr) == 1);
  REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&source), sizeof source) == 0);
  REQUIRE(::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) == 0);
  return fd;
}
}  // namespace

TEST_CASE("silent strangers cannot keep the real peer out, and refusals do not flood the log") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  auto listener_options = test::test_session_options(Role::Listener, key, log, "B");
  // Strangers would hold their slots for longer than the test waits for the peer: a peer that got
  // in only once they timed out fails it.
  listener_options.handshake_timeout = std::chrono::milliseconds(60000);
  const auto started = std::chrono::steady_clock::now();
  Session listener(listener_options);
  listener.start();
  const sockaddr_in address = test::loopback_address(listener.local_port());
  // More connections that never say anything than the listener keeps waiting for a hello, then
  // forty that send garbage at once, each from a network of its own (the loopback network has
  // them all), so that none is shed at accept for its network's rate.
  constexpr int kSilent = 320, kGarbage = 40;
  std::vector<int> strangers;
  for (int i = 0; i < kSilent + kGarbage; ++i) {
    const int fd = connect_from_net_session(address, "127." + std::to_string(1 + i / 200) + "." + std::to_string(i % 200) + ".1");
    if (i >= kSilent) {
      const std::string garbage(200, 'x');
      CHECK(::write(fd, garbage.data(), garbage.size()) > 0);
    }
    strangers.push_back(fd);
  }
  // Beyond the room for connections awaiting their hello, the newest were turned away at accept
  // (or, on a machine slow enough, the oldest dropped for them).
  REQUIRE(eventually_net_session([&] {
    const NetCounters c = listener.counters();
    return c.connections_turned_away + c.handshakes_dropped_for_room >= kSilent - 256;
  }));
  auto options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = listener.local_port();
  Session connector(options);
  const auto start = std::chrono::steady_clock::now();
  connector.start();
  CHECK(connector.wait_connected(kPatienceNetSession));
  INFO("connected after " << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
  // None of the strangers cost a key pair: the peer's hello alone made handshake state.
  NetCounters counters = listener.counters();
  CHECK(counters.handshakes_started == 1);
  INFO(counters.handshakes_dropped_for_room << " dropped for room, " << counters.connections_turned_away << " turned away, "
                                            << counters.handshakes_refused << " refused");
  for (const int fd : strangers) ::close(fd);
  // However many strangers, one line a second at most.
  const size_t refusal_lines = lines_with(log, "B", "refused"), dropped_lines = lines_with(log, "B", "dropped: too many"),
               turned_lines = lines_with(log, "B", "closed at accept");
  const size_t most_lines = most_lines_since(started);
  INFO(refusal_lines << " refusal lines, " << dropped_lines << " dropped lines, " << turned_lines << " turned-away lines, "
                     << most_lines << " of each at most");
  CHECK(refusal_lines <= most_lines);
  CHECK(dropped_lines <= most_lines);
  CHECK(turned_lines <= most_lines);
  CHECK(counters.to_json()["connections_turned_away"] == counters.connections_turned_away);
}

TEST_CASE("a flood from one network is shed at accept; the peer, from another or on its own address, gets in") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  const auto started = std::chrono::steady_clock::now();
  Session listener(test::test_session_options(Role::Listener, key, log, "B"));
  listener.start();
  const sockaddr_in address = test::loopback_address(listener.local_port());
  // Connections the listener is done with: closed unread, refused (the garbage), or dropped for
  // room among the handshakes under way.
  auto handled = [&] {
    const NetCounters c = listener.counters();
    return c.connections_shed + c.connections_turned_away + c.handshakes_refused + c.handshakes_dropped_for_room;
  };
  const std::string garbage(64, 'x');
  auto flood = [&](const std::string& from, int connections) {
    for (int i = 0; i < connections; ++i) {
      const int fd = connect_from_net_session(address, from);
      (void)!::write(fd, garbage.data(), garbage.size());
      ::close(fd);
    }
  };
  const auto flood_start = std::chrono::steady_clock::now();
  flood("127.0.5.2", 200);
  REQUIRE(eventually_net_session([&] { return handled() >= 200; }));
  // The burst (20) and what refills (10 a second) until the listener has taken the whole flood
  // are let in; the rest is closed unread. A slow machine takes longer, and lets in more.
  const double flood_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - flood_start).count();
  const uint64_t shed = listener.counters().connections_shed;
  INFO(shed << " of 200 shed, the flood taken in over " << flood_s << " s");
  CHECK(double(200 - std::min<uint64_t>(shed, 200)) <= 20 + 10 * flood_s);
  auto options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = listener.local_port();
  Session connector(options);
  connector.start();
  CHECK(connector.wait_connected(kPatienceNetSession));
  CHECK(listener.counters().connections_shed == shed);  // the peer's network has a rate of its own
  // The flooder's whole network (/24) is over its rate, not just its address.
  flood("127.0.5.77", 5);
  REQUIRE(eventually_net_session([&] { return listener.counters().connections_shed >= shed + 5; }));
  const uint64_t shed_with_network = listener.counters().connections_shed;
  CHECK(shed_with_network == shed + 5);

  // The peer's own address is never shed: a flood from it (its host, its network's NAT) still
  // lets the peer back in after the link is lost.
  const uint64_t handled_before = handled();
  flood("127.0.0.1", 200);
  REQUIRE(eventually_net_session([&] { return handled() >= handled_before + 200; }));
  CHECK(listener.counters().connections_shed == shed_with_network);
  const size_t shed_lines = lines_with(log, "B", "closed unread"), most_lines = most_lines_since(started);
  INFO(shed_lines << " lines of shed connections, " << most_lines << " at most at one a second");
  CHECK(shed_lines <= most_lines);
  CHECK(listener.counters().to_json()["connections_shed"] == shed_with_network);
}

TEST_CASE("a session refuses a weak key at construction") {
  test::LogLines log;
  CHECK_THROWS_WITH(Session(test::test_session_options(Role::Listener, SessionKey{}, log, "B")),
                    Catch::Contains("session key is weak") && Catch::Contains("keygen"));
}

namespace {

// A hand-driven connector: a raw socket speaking the handshake through a Handshake object.
struct RawConnector {
  asio::io_context io;
  asio::ip::tcp::socket socket{io};
  explicit RawConnector(uint16_t port) { socket.connect({asio::ip::make_address("127.0.0.1"), port}); }
  // The bytes that arrive until the peer closes (then *eof), or until `enough` of them have come;
  // what has come when kPatience passes, if neither happens.
  std::vector<uint8_t> read_until_closed(bool* eof, size_t enough = SIZE_MAX) {
    std::vector<uint8_t> got;
    const auto deadline = std::chrono::steady_clock::now() + kPatienceNetSession;
    socket.non_blocking(true);
    while (got.size() < enough && std::chrono::steady_clock::now() < deadline) {
      uint8_t buffer[256];
      std::error_code ec;
      const size_t n = socket.read_some(asio::buffer(buffer), ec);
      if (ec == asio::error::would_block) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        continue;
      }
      if (ec) {
        if (eof) *eof = true;
        break;
      }
      got.insert(got.end(), buffer, buffer + n);
    }
    socket.non_blocking(false);
    return got;
  }
};

}  // namespace

TEST_CASE("the listener sends nothing that proves the key before it has verified the connector's proof") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  Session listener(test::test_session_options(Role::Listener, key, log, "B"));
  listener.start();
  {
    // Hello for hello, then silence: the listener's hello is all it says (nothing keyed), until
    // its handshake timeout closes the connection.
    RawConnector raw(listener.local_port());
    Handshake connector(key, Role::Connector);
    asio::write(raw.socket, asio::buffer(connector.hello()));
    bool eof = false;
    const auto got = raw.read_until_closed(&eof);
    CHECK(got.size() == kHelloSize);
    CHECK(eof);
    REQUIRE(got.size() >= kHelloSize);
    CHECK_FALSE(connector.receive_hello(std::span(got).first(kHelloSize)));
    CHECK(log.contains("handshake timed out"));
  }
  {
    // A wrong proof: what comes back is no proof (the connector holds the right key and refuses
    // it), then the listener closes.
    RawConnector raw(listener.local_port());
    Handshake connector(key, Role::Connector);
    asio::write(raw.socket, asio::buffer(connector.hello()));
    std::array<uint8_t, kHelloSize> hello{};
    asio::read(raw.socket, asio::buffer(hello));
    REQUIRE_FALSE(connector.receive_hello(hello));
    auto proof = connector.proof();
    proof[31] ^= 0x80;
    asio::write(raw.socket, asio::buffer(proof));
    bool eof = false;
    const auto reply = raw.read_until_closed(&eof);
    CHECK(eof);
    REQUIRE(reply.size() == kProofSize);
    CHECK_THAT(*connector.verify_proof(reply), Catch::Contains("did not prove knowledge of the session key"));
    // (Its log line may be held back: refusals are logged once a second at most.)
    REQUIRE(eventually_net_session([&] { return listener.counters().handshakes_refused == 2; }));
    CHECK_THAT(listener.status().reason, Catch::Contains("did not prove knowledge of the session key"));
  }
  {
    // The right proof: the listener's proof follows and verifies.
    RawConnector raw(listener.local_port());
    Handshake connector(key, Role::Connector);
    asio::write(raw.socket, asio::buffer(connector.hello()));
    std::array<uint8_t, kHelloSize> hello{};
    asio::read(raw.socket, asio::buffer(hello));
    REQUIRE_FALSE(connector.receive_hello(hello));
    asio::write(raw.socket, asio::buffer(connector.proof()));
    std::array<uint8_t, kProofSize> proof{};
    asio::read(raw.socket, asio::buffer(proof));
    CHECK_FALSE(connector.verify_proof(proof));
    CHECK(listener.wait_connected(kPatienceNetSession));
  }
  CHECK(listener.counters().handshakes_refused == 2);
  CHECK(listener.counters().handshakes_ok == 1);
}

TEST_CASE("a peer of the previous protocol version gets a clear error naming both versions, both ways") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  // Version 2's hello: "RTHS" | version 2 | role | 0 | nonce[32] | ephemeral key[32], 72 bytes.
  auto v2_hello = [](Role role) {
    std::vector<uint8_t> hello = {'R', 'T', 'H', 'S', 2, 0, uint8_t(role), 0};
    hello.resize(72, 0x5a);
    return hello;
  };
  Session listener(test::test_session_options(Role::Listener, key, log, "B"));
  listener.start();
  RawConnector old_connector(listener.local_port());
  asio::write(old_connector.socket, asio::buffer(v2_hello(Role::Connector)));
  REQUIRE(eventually_net_session([&] { return listener.counters().handshakes_refused == 1; }));
  CHECK(log.contains("[B] connection with 127.0.0.1:"));
  CHECK(log.contains("refused: handshake: the peer speaks protocol version 2, this build version 3"));
  CHECK(listener.status().state == ConnectionState::Refused);
  // What the old peer received is our hello's first bytes, as far as the version, which it reads
  // and refuses: no key pair was made for it, nothing keyed sent.
  bool eof = false;
  const auto got = old_connector.read_until_closed(&eof);
  CHECK(eof);
  REQUIRE(got.size() == kHelloPrefixSize);
  CHECK(got[4] == 3);
  CHECK(listener.counters().handshakes_started == 0);

  // An old listener: the connector refuses it the same way.
  asio::io_context io;
  asio::ip::tcp::acceptor old_listener(io, {asio::ip::make_address("127.0.0.1"), 0});
  auto options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = old_listener.local_endpoint().port();
  Session connector(options);
  connector.start();
  asio::ip::tcp::socket accepted(io);
  old_listener.accept(accepted);
  asio::write(accepted, asio::buffer(v2_hello(Role::Listener)));
  REQUIRE(eventually_net_session([&] { return connector.status().state == ConnectionState::Refused; }));
  CHECK_THAT(connector.status().reason, Catch::Contains("peer speaks protocol version 2, this build version 3"));
}

TEST_CASE("a genuine hello played again is refused before any handshake state, and gets no reply") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  Session listener(test::test_session_options(Role::Listener, key, log, "B"));
  listener.start();
  Handshake genuine(key, Role::Connector);
  const auto hello = genuine.hello();
  {
    // The first time: the listener's hello comes back.
    RawConnector raw(listener.local_port());
    asio::write(raw.socket, asio::buffer(hello));
    std::array<uint8_t, kHelloSize> reply{};
    asio::read(raw.socket, asio::buffer(reply));
    CHECK_FALSE(genuine.receive_hello(reply));
    REQUIRE(eventually_net_session([&] { return listener.counters().handshakes_started == 1; }));
  }
  {
    // Recorded and played again, on a new connection: refused at the replay window, closed
    // without a word, no key pair made.
    RawConnector replay(listener.local_port());
    asio::write(replay.socket, asio::buffer(hello));
    bool eof = false;
    const auto got = replay.read_until_closed(&eof);
    CHECK(eof);
    CHECK(got.empty());
    REQUIRE(eventually_net_session([&] { return listener.counters().hellos_replayed == 1; }));
    CHECK(listener.counters().handshakes_started == 1);
    CHECK_THAT(listener.status().reason, Catch::Contains("no later than the last one accepted"));
  }
  // The real connector's next hello is later: it gets in.
  auto options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = listener.local_port();
  Session connector(options);
  connector.start();
  CHECK(connector.wait_connected(kPatienceNetSession));
  CHECK(listener.counters().handshakes_started == 2);
}

TEST_CASE("a listener that refuses once does not end the connector's attempts: the real listener, up later, gets the call") {
  test::LogLines log;
  const SessionKey key = random_session_key();
  // A fake listener on the port first: an older release's, answering with its version 2 hello.
  asio::io_context io;
  auto fake = std::make_unique<asio::ip::tcp::acceptor>(io, asio::ip::tcp::endpoint{asio::ip::make_address("127.0.0.1"), 0});
  const uint16_t port = fake->local_endpoint().port();
  auto options = test::test_session_options(Role::Connector, key, log, "A");
  options.port = port;
  Session connector(options);
  connector.start();
  {
    asio::ip::tcp::socket accepted(io);
    fake->accept(accepted);
    std::vector<uint8_t> old_hello = {'R', 'T', 'H', 'S', 2, 0, uint8_t(Role::Listener), 0};
    old_hello.resize(72, 0x5a);
    asio::write(accepted, asio::buffer(old_hello));
    REQUIRE(eventually_net_session([&] { return connector.status().state == ConnectionState::Refused; }));
    CHECK_THAT(connector.status().reason, Catch::Contains("peer speaks protocol version 2, this build version 3"));
  }
  fake.reset();  // the fake goes; the real listener comes up on the same port
  auto listener_options = test::test_session_options(Role::Listener, key, log, "B");
  listener_options.port = port;
  Session listener(listener_options);
  listener.start();
  CHECK(connector.wait_connected(kPatienceNetSession));
  CHECK(connector.counters().handshakes_refused >= 1);
  CHECK(connector.counters().handshakes_ok == 1);
}
