// The session's CPU pieces: the newest-wins mailbox between stages, the fair GPU turn, the event
// log and the latency summary.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "session/closest_in_time.h"
#include "session/event_log.h"
#include "session/fair_mutex.h"
#include "session/latency_stats.h"
#include "session/mailbox.h"
#include "session/timed_history.h"

using namespace rt::session;

TEST_CASE("mailbox: the newest value wins and replaced ones count as dropped") {
  Mailbox<int> box;
  REQUIRE_FALSE(box.take());
  REQUIRE_FALSE(box.put(1));
  REQUIRE(box.put(2));
  REQUIRE(box.put(3));
  REQUIRE(box.take() == 3);
  REQUIRE_FALSE(box.take());
  REQUIRE(box.dropped() == 2);
  REQUIRE(box.delivered() == 1);
  REQUIRE(box.offered() == 3);
}

TEST_CASE("mailbox: wait_take times out empty, wakes on put and on close") {
  Mailbox<int> box;
  REQUIRE_FALSE(box.wait_take(std::chrono::milliseconds(5)));
  std::thread producer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    box.put(7);
  });
  REQUIRE(box.wait_take(std::chrono::seconds(5)) == 7);
  producer.join();
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    box.close();
  });
  const auto start = std::chrono::steady_clock::now();
  REQUIRE_FALSE(box.wait_take(std::chrono::seconds(5)));
  REQUIRE(std::chrono::steady_clock::now() - start < std::chrono::seconds(4));
  closer.join();
  REQUIRE(box.closed());
  box.put(9);  // a value put after close can still be drained
  REQUIRE(box.wait_take(std::chrono::milliseconds(1)) == 9);
}

TEST_CASE("mailbox: a slow consumer sees only fresh values, every value is either taken or dropped") {
  Mailbox<int> box;
  constexpr int kCount = 2000;
  std::atomic<bool> done{false};
  std::vector<int> seen;
  std::thread consumer([&] {
    while (!done || box.offered() != box.delivered() + box.dropped()) {
      if (auto v = box.wait_take(std::chrono::milliseconds(1))) seen.push_back(*v);
    }
  });
  for (int i = 0; i < kCount; ++i) box.put(i);
  done = true;
  consumer.join();
  REQUIRE(box.delivered() + box.dropped() == kCount);
  REQUIRE(seen.size() == box.delivered());
  REQUIRE(std::is_sorted(seen.begin(), seen.end()));  // never an older value after a newer one
  REQUIRE(seen.back() == kCount - 1);
}

TEST_CASE("fair mutex: waiting threads are served in arrival order") {
  FairMutex mutex;
  std::vector<int> order;
  mutex.lock();
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back([&, i] {
      std::lock_guard lock(mutex);
      order.push_back(i);
    });
    while (mutex.waiting() != uint64_t(i + 1)) std::this_thread::yield();  // thread i is queued before i+1
  }
  mutex.unlock();
  for (auto& t : threads) t.join();
  REQUIRE(order == std::vector<int>{0, 1, 2, 3});
}

TEST_CASE("fair mutex: an urgent waiter goes before the queued ones, after the turn in progress") {
  FairMutex mutex;
  std::vector<std::string> order;
  mutex.lock();
  std::vector<std::thread> threads;
  for (int i = 0; i < 2; ++i) {
    threads.emplace_back([&, i] {
      std::lock_guard lock(mutex);
      order.push_back("normal" + std::to_string(i));
    });
    while (mutex.waiting() != uint64_t(i + 1)) std::this_thread::yield();
  }
  threads.emplace_back([&] {
    UrgentTurn turn(mutex);
    order.push_back("urgent");
  });
  while (mutex.waiting() != 3) std::this_thread::yield();
  order.push_back("holder");
  mutex.unlock();
  for (auto& t : threads) t.join();
  REQUIRE(order == std::vector<std::string>{"holder", "urgent", "normal0", "normal1"});
}

TEST_CASE("event log: one JSON object per line with event, site and time; read back") {
  const auto path = std::filesystem::temp_directory_path() / "rt_test_session_events.jsonl";
  {
    EventLog log(path, "B");
    std::vector<std::thread> writers;
    for (int w = 0; w < 4; ++w)
      writers.emplace_back([&, w] {
        for (int i = 0; i < 50; ++i) log.write(i % 2 ? "touch_end" : "touch_start", uint64_t(w * 1000 + i), {{"w", w}});
      });
    for (auto& t : writers) t.join();
    REQUIRE(log.count("touch_start") == 100);
    REQUIRE(log.count("motor_pulse") == 0);
  }
  const auto events = read_events(path);
  REQUIRE(events.size() == 200);
  for (const auto& e : events) {
    REQUIRE(e["site"] == "B");
    REQUIRE(e.contains("t_us"));
    REQUIRE(e.contains("w"));
  }
  std::ofstream(path, std::ios::app) << "not json\n";
  REQUIRE_THROWS_WITH(read_events(path), Catch::Contains(":201: not a JSON object"));
  REQUIRE_THROWS_WITH(EventLog("/nonexistent-dir/x.jsonl", "A"), Catch::Contains("cannot write the event log"));
  std::filesystem::remove(path);
}

TEST_CASE("latency stats: median, p90, max; empty gives nulls; NaN ignored") {
  LatencyStats stats;
  REQUIRE(stats.to_json()["median_ms"].is_null());
  REQUIRE(std::isnan(stats.median()));
  for (int i = 1; i <= 11; ++i) stats.add(double(i));
  stats.add(NAN);
  const auto json = stats.to_json();
  REQUIRE(json["count"] == 11);
  REQUIRE(json["median_ms"].get<double>() == Approx(6.0));
  REQUIRE(json["p90_ms"].get<double>() == Approx(10.0));
  REQUIRE(json["max_ms"].get<double>() == Approx(11.0));
  REQUIRE(json["mean_ms"].get<double>() == Approx(6.0));
  // The recent median follows the newest samples only, and takes all of them when asked for more.
  REQUIRE(stats.recent_median(3) == Approx(10.0));
  REQUIRE(stats.recent_median(1) == Approx(11.0));
  REQUIRE(stats.recent_median(1000) == Approx(6.0));
  REQUIRE(std::isnan(LatencyStats().recent_median(5)));
  for (int i = 0; i < 5; ++i) stats.add(100.0);
  REQUIRE(stats.recent_median(5) == Approx(100.0));
  REQUIRE(stats.median() == Approx(9.0));
}

TEST_CASE("closest in time: nearest timestamp either side, earlier on a tie, end when empty") {
  const std::vector<uint64_t> stamps = {100, 120, 140, 160};
  auto at = [&](uint64_t target) {
    const auto it = closest_in_time(stamps.begin(), stamps.end(), target, [](uint64_t t) { return t; });
    return it == stamps.end() ? uint64_t(0) : *it;
  };
  REQUIRE(at(0) == 100);
  REQUIRE(at(129) == 120);
  REQUIRE(at(131) == 140);
  REQUIRE(at(130) == 120);
  REQUIRE(at(1'000'000) == 160);
  const std::vector<uint64_t> none;
  REQUIRE(closest_in_time(none.begin(), none.end(), 5, [](uint64_t t) { return t; }) == none.end());
}

TEST_CASE("timed history: closest entry to a time, bounded, shared between threads") {
  TimedHistory<int> history(3);
  REQUIRE_FALSE(history.closest(100));
  history.add(100, 1);
  history.add(200, 2);
  history.add(300, 3);
  CHECK(history.closest(0)->second == 1);
  CHECK(history.closest(149)->second == 1);
  CHECK(history.closest(150)->second == 1);  // a tie: the earlier
  CHECK(history.closest(151)->second == 2);
  CHECK(history.closest(10'000)->first == 300);
  history.add(400, 4);  // 100 falls out
  CHECK(history.size() == 3);
  CHECK(history.closest(0)->second == 2);

  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int i = 0; i < 2000; ++i) history.add(uint64_t(1000 + i), i);
    done = true;
  });
  while (!done) {
    const auto entry = history.closest(UINT64_MAX);
    REQUIRE(entry);
    REQUIRE((entry->first < 1000 || uint64_t(entry->second) == entry->first - 1000));
  }
  writer.join();
  CHECK(history.closest(UINT64_MAX)->second == 1999);
}
