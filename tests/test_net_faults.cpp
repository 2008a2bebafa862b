// Fault injection through the loopback proxy: delay, jitter, loss (each lost record cuts the
// link), a record deleted in the path, a disconnect in the middle, garbage in the stream. The session goes on (or reconnects), nothing crashes, and the counts
// add up; they are printed as JSON for the record.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>

#include "net_test_messages.h"
#include "net_test_sessions.h"
#include "time/monotonic_clock.h"

using namespace rt;
using namespace rt::net;
using rt::test::eventually;

// The largest single allocation since the last reset, whichever thread made it: a receiver that
// sized a buffer by an unauthenticated record length would show it here.
static std::atomic<size_t> g_largest_allocation{0};
static void note_allocation(size_t size) {
  size_t seen = g_largest_allocation.load(std::memory_order_relaxed);
  while (size > seen && !g_largest_allocation.compare_exchange_weak(seen, size, std::memory_order_relaxed)) {
  }
}
#if defined(__SANITIZE_ADDRESS__)
// Under AddressSanitizer its allocator is asked (a replaced operator new would not match the
// deletes its runtime makes); its hook sees malloc and operator new alike. (GCC ships no header
// declaring it; its runtime has it, as LLVM's sanitizer/allocator_interface.h declares it.)
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*)(const volatile void*, size_t), void (*)(const volatile void*));
static void asan_allocated(const volatile void*, size_t size) { note_allocation(size); }
static void asan_freed(const volatile void*) {}
[[maybe_unused]] static const int g_allocation_hook = __sanitizer_install_malloc_and_free_hooks(asan_allocated, asan_freed);
#else
// (Out of line: GCC takes free() inlined after a new-expression for a mismatch.)
__attribute__((noinline)) void* operator new(size_t size) {
  note_allocation(size);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, size_t) noexcept { std::free(p); }
#endif

namespace {

constexpr size_t kTouch = size_t(MessageType::TouchEvent) - 1;

struct ProxiedLink {
  test::LogLines log;
  SessionKey key = random_session_key();
  Session listener;
  std::unique_ptr<FaultProxy> proxy;
  std::unique_ptr<Session> connector;
  explicit ProxiedLink(const FaultOptions& faults, std::chrono::milliseconds reconnect_min = std::chrono::milliseconds(20),
                       std::chrono::milliseconds lost_after = std::chrono::milliseconds(1500))
      : listener(listener_options(lost_after)) {
    listener.start();
    proxy = std::make_unique<FaultProxy>("127.0.0.1", listener.local_port(), faults);
    proxy->start();
    auto options = test::test_session_options(Role::Connector, key, log, "A");
    options.port = proxy->port();
    options.reconnect_min = reconnect_min;
    options.lost_after = lost_after;
    options.handshake_timeout = lost_after;
    connector = std::make_unique<Session>(options);
    connector->start();
  }
  SessionOptions listener_options(std::chrono::milliseconds lost_after) {
    auto options = test::test_session_options(Role::Listener, key, log, "B");
    options.lost_after = lost_after;
    options.handshake_timeout = lost_after;
    return options;
  }
  void report(const std::string& what) {
    std::cout << what << ":\n  proxy " << proxy->counts().to_json().dump() << "\n  connector "
              << connector->counters().to_json().dump() << "\n  listener " << listener.counters().to_json().dump() << "\n";
  }
};

}  // namespace

TEST_CASE("delay and jitter: everything arrives, in order, late by at least the delay") {
  FaultOptions faults;
  faults.delay = std::chrono::milliseconds(30);
  faults.jitter = std::chrono::milliseconds(20);
  ProxiedLink link(faults);
  std::mutex mutex;
  std::vector<std::pair<uint64_t, uint64_t>> arrivals;  // sent at, received at (one process: one clock)
  link.listener.set_handler([&](const Message& m) {
    if (const auto* touch = std::get_if<TouchEventMessage>(&m)) {
      std::lock_guard lock(mutex);
      arrivals.emplace_back(touch->timestamp_us, monotonic_now_us());
    }
  });
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  for (int i = 0; i < 20; ++i) {
    link.connector->send(TouchEventMessage{monotonic_now_us(), TouchEventMessage::Kind::Start, 0});
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  REQUIRE(eventually([&] {
    std::lock_guard lock(mutex);
    return arrivals.size() == 20;
  }));
  uint64_t max_latency = 0;
  for (size_t i = 0; i < arrivals.size(); ++i) {
    CHECK(arrivals[i].second - arrivals[i].first >= 30'000);
    if (i > 0) CHECK(arrivals[i].first > arrivals[i - 1].first);  // in order
    max_latency = std::max(max_latency, arrivals[i].second - arrivals[i].first);
  }
  CHECK(max_latency < 500'000);
  CHECK(link.proxy->counts().records_dropped == 0);
  CHECK(link.listener.counters().rejected == 0);
  CHECK(link.connector->status().connected());
  link.report("delay 30 ms + jitter 20 ms");
}

TEST_CASE("loss: a lost record cuts the link there, the session rebuilds it, every record that arrives is in sequence") {
  FaultOptions faults;
  faults.loss = 0.02;
  faults.seed = 3;
  ProxiedLink link(faults);
  std::mutex mutex;
  std::vector<uint64_t> arrived;
  link.listener.set_handler([&](const Message& m) {
    if (const auto* touch = std::get_if<TouchEventMessage>(&m)) {
      std::lock_guard lock(mutex);
      arrived.push_back(touch->timestamp_us);
    }
  });
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  // Touch events one by one, each only once the link is up: a touch written into a link that is
  // then cut is gone (no application acknowledgements), one not yet written goes again.
  uint64_t sent = 0;
  REQUIRE(eventually(
      [&] {
        if (link.connector->status().connected()) link.connector->send(TouchEventMessage{++sent, TouchEventMessage::Kind::Start, 0});
        std::this_thread::sleep_for(std::chrono::milliseconds(3));
        return link.proxy->counts().records_dropped >= 3 && sent >= 200;
      },
      std::chrono::seconds(20)));
  // A last one that gets through (sent again under a new number while a cut takes it).
  int polls = 0;
  REQUIRE(eventually(
      [&] {
        {
          std::lock_guard lock(mutex);
          if (!arrived.empty() && arrived.back() == sent) return true;
        }
        if (polls++ % 100 == 0) link.connector->send(TouchEventMessage{++sent, TouchEventMessage::Kind::End, 0});
        return false;
      },
      std::chrono::seconds(10)));
  const NetCounters in = link.listener.counters(), out = link.connector->counters();
  const FaultCounts proxy = link.proxy->counts();
  INFO(proxy.to_json().dump());
  // No gap was ever seen: a stream with a hole in it is never delivered.
  CHECK(in.rejected == 0);
  CHECK(out.rejected == 0);
  CHECK(in.records_out_of_sequence + out.records_out_of_sequence == 0);
  CHECK(out.reconnects >= 3);
  CHECK(out.connections_lost >= 3);
  CHECK(proxy.disconnects == 0);  // the cuts are the losses'
  std::lock_guard lock(mutex);
  CHECK(arrived.size() <= sent);
  CHECK(arrived.size() > sent / 2);
  for (size_t i = 1; i < arrived.size(); ++i) CHECK(arrived[i] > arrived[i - 1]);  // in order, none twice
  link.report("loss 2% (each lost record cuts the link)");
}

TEST_CASE("a record deleted on the way (a counter gap) is refused, the connection rebuilt, nothing already received lost") {
  ProxiedLink link(FaultOptions{});
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  REQUIRE(link.listener.wait_connected(std::chrono::seconds(3)));
  link.connector->send(EyeMessage{1, {0, 0, -0.7}, true});
  link.connector->send(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  link.connector->send(TouchEventMessage{2, TouchEventMessage::Kind::End, 0});
  REQUIRE(eventually([&] { return link.listener.counters().messages_in[kTouch] == 2; }));
  // The attacker in the path picks the touch events out by their size: 1-byte fragment flag +
  // 12-byte message header + 26-byte touch + 16-byte tag.
  const uint32_t touch_record = uint32_t(kRecordFlagSize + encode_message(TouchEventMessage{}).size() + kRecordTagSize);
  link.proxy->delete_next_record(touch_record);
  link.connector->send(TouchEventMessage{3, TouchEventMessage::Kind::Start, 0});
  // The next record (a heartbeat, at the latest) reveals the gap.
  REQUIRE(eventually([&] { return link.listener.counters().records_out_of_sequence == 1; }));
  CHECK(link.proxy->counts().records_deleted == 1);
  const NetCounters b = link.listener.counters();
  CHECK(b.rejected_by_reason.at("out_of_sequence") == 1);
  CHECK_THAT(b.last_rejection, Catch::Contains("out of sequence") && Catch::Contains("1 deleted on the way"));
  REQUIRE(eventually([&] { return link.listener.counters().connections_lost == 1; }));
  CHECK(link.log.contains("[B] rejected: record"));
  CHECK(link.log.contains("[B] connection with"));
  // Rebuilt by the connector, as any dead connection is; the session goes on.
  REQUIRE(eventually([&] { return link.connector->counters().reconnects == 1 && link.connector->status().connected(); }));
  link.connector->send(TouchEventMessage{4, TouchEventMessage::Kind::End, 0});
  REQUIRE(eventually([&] { return link.listener.counters().messages_in[kTouch] == 4; }));
  // What had arrived before the gap is all there, once each; the deleted touch was not
  // acknowledged, so it went again on the new connection, before the one sent after it.
  const auto touches = link.listener.take_touch_events();
  REQUIRE(touches.size() == 4);
  for (size_t i = 0; i < touches.size(); ++i) {
    CHECK(touches[i].timestamp_us == i + 1);
    CHECK(touches[i].sequence == i + 1);
    CHECK(touches[i].sender_session == touches[0].sender_session);
  }
  CHECK(touches[0].sender_session != 0);
  CHECK(link.listener.take_eye().has_value());
  CHECK(link.listener.counters().reconnects == 1);
  CHECK(link.connector->counters().touches_resent >= 1);
  // The first two may go again too (a heartbeat's acknowledgement may not have come back before
  // the cut); any copy is dropped, never delivered twice.
  CHECK(link.listener.counters().touch_duplicates_in == link.connector->counters().touches_resent - 1);
  link.report("a touch record deleted in the path");
}

TEST_CASE("a disconnect in the middle: both sides see the remote lost, reconnect, and go on") {
  ProxiedLink link(FaultOptions{}, std::chrono::milliseconds(300));
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  REQUIRE(link.listener.wait_connected(std::chrono::seconds(3)));
  link.connector->send(EyeMessage{1, {0, 0, -0.7}, true});
  REQUIRE(eventually([&] { return link.listener.take_eye().has_value(); }));

  const uint64_t cut = monotonic_now_us();
  link.proxy->disconnect_now();
  REQUIRE(eventually([&] { return link.connector->status().state == ConnectionState::Lost; }, std::chrono::milliseconds(1000)));
  const ConnectionStatus lost = link.connector->status();
  CHECK(lost.since_us >= cut);
  CHECK_FALSE(lost.reason.empty());
  // Meanwhile the local side keeps going: sending does not block and nothing is thrown.
  link.connector->send(EyeMessage{2, {0, 0, -0.71}, true});
  link.connector->send(TouchEventMessage{3, TouchEventMessage::Kind::Start, 0});

  REQUIRE(eventually([&] { return link.connector->status().connected() && link.listener.status().connected(); }));
  REQUIRE(eventually([&] { return link.listener.take_touch_events().size() == 1; }));
  // The eye waited in its slot and goes out after the touch (touch events first), so it may
  // still be on its way when the touch is in.
  std::optional<EyeMessage> eye;
  REQUIRE(eventually([&] { return (eye = link.listener.take_eye()).has_value(); }));
  CHECK(eye->timestamp_us == 2);
  const NetCounters a = link.connector->counters(), b = link.listener.counters();
  CHECK(a.connections_lost == 1);
  CHECK(a.reconnects == 1);
  CHECK(b.reconnects == 1);
  CHECK(b.handshakes_ok == 2);
  CHECK(link.proxy->counts().disconnects == 1);
  CHECK(link.log.contains("[A] connection with"));
  link.report("disconnect and reconnect");
}

TEST_CASE("an acknowledged touch event is not sent again after a reconnect; a new run's touch events are new") {
  ProxiedLink link(FaultOptions{});
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  link.connector->send(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  REQUIRE(eventually([&] { return link.connector->counters().touches_acked == 1; }));
  link.proxy->disconnect_now();
  REQUIRE(eventually([&] { return link.connector->counters().reconnects == 1 && link.connector->status().connected(); }));
  link.connector->send(TouchEventMessage{2, TouchEventMessage::Kind::End, 0});
  REQUIRE(eventually([&] { return link.listener.counters().messages_in[kTouch] == 2; }));
  REQUIRE(eventually([&] { return link.connector->counters().touches_acked == 2; }));
  CHECK(link.connector->counters().touches_resent == 0);
  CHECK(link.listener.counters().touch_duplicates_in == 0);
  auto touches = link.listener.take_touch_events();
  REQUIRE(touches.size() == 2);
  CHECK(touches[0].sequence == 1);
  CHECK(touches[1].sequence == 2);

  // The connecting site's run ends and a new one starts: its numbering starts at 1 again, under
  // a new session id, and the listener takes its touch events as new ones.
  link.connector.reset();
  auto options = test::test_session_options(Role::Connector, link.key, link.log, "A");
  options.port = link.proxy->port();
  link.connector = std::make_unique<Session>(options);
  link.connector->start();
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  link.connector->send(TouchEventMessage{3, TouchEventMessage::Kind::Start, 0});
  REQUIRE(eventually([&] { return link.listener.counters().messages_in[kTouch] == 3; }));
  touches = link.listener.take_touch_events();
  REQUIRE(touches.size() == 1);
  CHECK(touches[0].sequence == 1);
  CHECK(touches[0].timestamp_us == 3);
  CHECK(link.listener.counters().touch_duplicates_in == 0);
  link.report("touch acknowledgements over a reconnect and a new run");
}

TEST_CASE("garbage in the stream: rejected, the connection is rebuilt, the session goes on") {
  ProxiedLink link(FaultOptions{});
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  REQUIRE(link.listener.wait_connected(std::chrono::seconds(3)));
  link.proxy->inject_garbage_now(64);
  REQUIRE(eventually([&] { return link.listener.counters().connections_lost >= 1; }));
  const NetCounters b = link.listener.counters();
  CHECK(b.rejected >= 1);
  CHECK(b.rejected_by_reason.count("record_oversize") + b.rejected_by_reason.count("auth_failed") >= 1);
  // The connector learns of it when the listener closes, and comes back on a new connection.
  REQUIRE(eventually([&] { return link.connector->counters().reconnects == 1 && link.connector->status().connected(); }));
  link.connector->send(TouchEventMessage{9, TouchEventMessage::Kind::End, 0});
  REQUIRE(eventually([&] { return link.listener.take_touch_events().size() == 1; }));
  CHECK(link.listener.counters().reconnects == 1);
  CHECK(link.proxy->counts().garbage_injections == 1);
  link.report("64 garbage bytes");
}

TEST_CASE("fault options on a timer, as the demo will use them") {
  FaultOptions faults;
  faults.disconnect_after = std::chrono::milliseconds(300);
  faults.garbage_after = std::chrono::milliseconds(900);
  ProxiedLink link(faults);
  REQUIRE(eventually([&] { return link.proxy->counts().disconnects == 1 && link.proxy->counts().garbage_injections == 1; }));
  // The session goes on: an eye sent now and then gets through. (An eye written into a connection
  // that is already dying is gone: newest wins, nothing is resent but touch events.)
  REQUIRE(eventually([&] {
    link.connector->send(EyeMessage{5, {0, 0, -0.6}, true});
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return link.listener.take_eye().has_value();
  }));
  const NetCounters b = link.listener.counters();
  // The garbage broke either the session (rejected) or, had it landed in a reconnect's handshake,
  // that handshake (refused).
  CHECK(b.rejected + b.handshakes_refused >= 1);
  CHECK(b.connections_lost >= 1);
  CHECK(link.connector->counters().reconnects >= 1);
  link.report("timed disconnect and garbage");
}

TEST_CASE("a link gone silent: heartbeats time out on both sides, handshakes time out, then it recovers") {
  ProxiedLink link(FaultOptions{}, std::chrono::milliseconds(20), std::chrono::milliseconds(300));
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(3)));
  REQUIRE(link.listener.wait_connected(std::chrono::seconds(3)));
  link.proxy->set_blackhole(true);
  REQUIRE(eventually([&] {
    return link.connector->counters().connections_lost == 1 && link.listener.counters().connections_lost == 1;
  }));
  // Whichever side's heartbeat timer fires first notices the silence; the other may then see the
  // proxy close its side.
  CHECK(link.log.contains("lost: no data from the peer for"));
  const uint64_t lost_since = link.connector->status().since_us;
  // The connector keeps trying; its handshakes vanish into the blackhole and time out. It is
  // still "lost since" the same moment: a timeout is not a refusal.
  REQUIRE(eventually([&] { return link.connector->counters().handshakes_refused >= 1; }));
  // Expected while the link is down: counted, not logged one by one.
  CHECK_FALSE(link.log.contains("refused: handshake timed out"));
  const ConnectionStatus status = link.connector->status();
  CHECK(status.state == ConnectionState::Lost);
  CHECK(status.since_us == lost_since);
  link.proxy->set_blackhole(false);
  REQUIRE(eventually([&] { return link.connector->status().connected() && link.listener.status().connected(); }));
  link.connector->send(TouchEventMessage{4, TouchEventMessage::Kind::Start, 0});
  REQUIRE(eventually([&] { return link.listener.take_touch_events().size() == 1; }));
  CHECK(link.proxy->counts().bytes_swallowed > 0);
  // One line says it is back, how long it was down and what the attempts met.
  CHECK(link.log.contains("[A] session re-established with"));
  CHECK(link.log.contains("attempts failed meanwhile, the last: "));
  link.report("blackhole");
}

TEST_CASE("a record length rewritten in the path: no buffer beyond one record's bound, the link rebuilt within the liveness timeout") {
  const auto lost_after = std::chrono::milliseconds(1500);
  ProxiedLink link(FaultOptions{}, std::chrono::milliseconds(20), lost_after);
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(20)));
  REQUIRE(link.listener.wait_connected(std::chrono::seconds(20)));
  link.connector->send(TouchEventMessage{1, TouchEventMessage::Kind::Start, 0});
  REQUIRE(eventually([&] { return link.listener.counters().messages_in[kTouch] == 1; }, std::chrono::seconds(20)));

  // The old limit, a whole portrait's worth: refused at once, nothing of that size allocated.
  g_largest_allocation = 0;
  link.proxy->rewrite_next_record_length(uint32_t(kMaxMessageSize + kRecordTagSize));
  REQUIRE(eventually([&] { return link.listener.counters().connections_lost == 1; }, std::chrono::seconds(20)));
  CHECK(link.listener.counters().rejected_by_reason.at("record_oversize") == 1);
  CHECK(g_largest_allocation.load() <= kMaxRecordCiphertext);
  REQUIRE(eventually([&] { return link.connector->status().connected() && link.listener.status().connected(); },
                     std::chrono::seconds(20)));

  // The longest a record may be: accepted as a length, but what follows in the stream (the
  // heartbeats, a few dozen bytes each) never completes it into an authentic record, and bytes
  // that are no record are no sign of life: the listener finds the link dead within its liveness
  // timeout (plus a heartbeat period for its check), and it is rebuilt. Touch events written
  // meanwhile arrive on the new link, acknowledged there.
  g_largest_allocation = 0;
  const uint64_t lost_before = link.listener.counters().connections_lost;
  link.proxy->rewrite_next_record_length(uint32_t(kMaxRecordCiphertext));
  // The next record the connector sends is the one rewritten: a touch event, then its kin.
  link.connector->send(TouchEventMessage{2, TouchEventMessage::Kind::End, 0});
  REQUIRE(eventually([&] { return link.proxy->counts().lengths_rewritten == 2; }, std::chrono::seconds(20)));
  const auto tampered = std::chrono::steady_clock::now();
  REQUIRE(eventually([&] { return link.listener.counters().connections_lost == lost_before + 1; }, std::chrono::seconds(20)));
  const double detected_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tampered).count();
  CHECK(g_largest_allocation.load() <= kMaxRecordCiphertext);
  CHECK_THAT(link.listener.status().reason, Catch::Contains("no data from the peer"));
  REQUIRE(eventually([&] { return link.connector->status().connected() && link.listener.status().connected(); },
                     std::chrono::seconds(20)));
  const double rebuilt_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tampered).count();
  REQUIRE(eventually([&] { return link.listener.counters().messages_in[kTouch] == 2; }, std::chrono::seconds(20)));
  std::cout << "a record length rewritten to " << kMaxRecordCiphertext << ": the listener found the link dead after "
            << detected_s * 1000 << " ms (liveness timeout " << lost_after.count() << " ms), rebuilt after " << rebuilt_s * 1000
            << " ms\n";
  // The heartbeat period (50 ms here) is the resolution of the check; a loaded machine gets half
  // a second more.
  CHECK(detected_s < std::chrono::duration<double>(lost_after).count() + 0.5);
  link.report("record lengths rewritten in the path");
}

TEST_CASE("a slow link: a portrait takes longer than the liveness timeout, each of its records comes within it, the link stays up") {
  const PortraitMessage portrait = test::test_portrait(640, 480, 9, 3);
  const auto bytes = encode_message(portrait);
  REQUIRE(bytes.size() > 4 * kMaxRecordPayload);
  // The whole portrait takes three seconds through the bottleneck, twice the liveness timeout;
  // one record of it a fraction of that.
  FaultOptions faults;
  faults.bytes_per_second = double(bytes.size()) / 3.0;
  const auto lost_after = std::chrono::milliseconds(1500);
  ProxiedLink link(faults, std::chrono::milliseconds(20), lost_after);
  REQUIRE(link.connector->wait_connected(std::chrono::seconds(20)));
  REQUIRE(link.listener.wait_connected(std::chrono::seconds(20)));
  const auto sent = std::chrono::steady_clock::now();
  link.connector->send_encoded(MessageType::Portrait, bytes);
  std::optional<PortraitMessage> got;
  REQUIRE(eventually([&] { return (got = link.listener.take_portrait()).has_value(); }, std::chrono::seconds(30)));
  const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  std::cout << "a portrait of " << bytes.size() << " bytes at " << faults.bytes_per_second / 1e3 << " kB/s: arrived after "
            << took_s * 1000 << " ms, liveness timeout " << lost_after.count() << " ms\n";
  CHECK(took_s > std::chrono::duration<double>(lost_after).count());
  CHECK(got->frame_index == portrait.frame_index);
  CHECK(std::memcmp(got->depth.texels.data(), portrait.depth.texels.data(), portrait.depth.texels.size() * 4) == 0);
  CHECK(link.listener.counters().connections_lost == 0);
  CHECK(link.connector->counters().connections_lost == 0);
  CHECK(link.listener.counters().handshakes_ok == 1);
  link.report("a slow link");
}
