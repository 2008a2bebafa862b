#include "net/fault_proxy.h"

#include <asio.hpp>
#include <cstring>
#include <deque>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "net/message_codec.h"
#include "net/secure_channel.h"

namespace rt::net {

nlohmann::json FaultCounts::to_json() const {
  return {{"connections", connections},   {"records_forwarded", records_forwarded}, {"records_dropped", records_dropped},
          {"records_deleted", records_deleted},
          {"lengths_rewritten", lengths_rewritten},
          {"garbage_injections", garbage_injections}, {"garbage_bytes", garbage_bytes}, {"disconnects", disconnects},
          {"bytes_swallowed", bytes_swallowed}};
}

namespace {

using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

// One direction of one proxied connection.
struct Pipe {
  Pipe(tcp::socket& from, tcp::socket& to, asio::io_context& io) : from(from), to(to), timer(io) {}
  tcp::socket& from;
  tcp::socket& to;
  asio::steady_timer timer;
  int handshake_stage = 0;  // 0: hello next, 1: proof next, 2: records
  bool raw = false;         // framing lost (garbage from an endpoint): forward bytes as they come
  std::vector<uint8_t> buffer;
  struct Item {
    Clock::time_point release;
    std::vector<uint8_t> bytes;
    bool cut = false;  // a lost record: the link is cut here, when it would have arrived
  };
  std::deque<Item> queue;
  Clock::time_point last_release{};
  bool writing = false, waiting = false;
};

struct Pair {
  explicit Pair(asio::io_context& io)
      : client(io), server(io), up(client, server, io), down(server, client, io) {}
  tcp::socket client, server;
  Pipe up, down;  // up: connector -> listener
  bool closed = false;
  bool swallowed = false;  // the blackhole ate some of its bytes
};
using PairPtr = std::shared_ptr<Pair>;

}  // namespace

struct FaultProxy::Impl {
  Impl(std::string host, uint16_t port, FaultOptions o)
      : target_host(std::move(host)), target_port(port), options(o), acceptor(io), trigger_disconnect(io),
        trigger_garbage(io), random(o.seed) {}

  std::string target_host;
  uint16_t target_port;
  FaultOptions options;
  asio::io_context io;
  tcp::acceptor acceptor;
  asio::steady_timer trigger_disconnect, trigger_garbage;
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work;
  std::thread thread;
  std::set<PairPtr> pairs;
  std::mt19937 random;
  bool closing = false;
  bool blackhole = false;
  std::optional<uint32_t> delete_length;  // delete the next record of this ciphertext length
  std::optional<uint32_t> rewrite_length;  // write this length into the next record's header
  uint16_t bound_port = 0;
  mutable std::mutex mutex;
  FaultCounts counts;

  void close(const PairPtr& p) {
    if (p->closed) return;
    p->closed = true;
    std::error_code ignored;
    p->client.close(ignored);
    p->server.close(ignored);
    p->up.timer.cancel();
    p->down.timer.cancel();
    pairs.erase(p);
  }

  void accept() {
    acceptor.async_accept([this](std::error_code e, tcp::socket socket) {
      if (closing) return;
      if (!e) {
        auto p = std::make_shared<Pair>(io);
        p->client = std::move(socket);
        pairs.insert(p);
        {
          std::lock_guard lock(mutex);
          ++counts.connections;
        }
        std::error_code ec;
        tcp::resolver resolver(io);
        const auto endpoints = resolver.resolve(target_host, std::to_string(target_port), ec);
        if (ec) {
          close(p);
        } else {
          asio::async_connect(p->server, endpoints, [this, p](std::error_code e2, const tcp::endpoint&) {
            if (e2 || p->closed) return close(p);
            p->client.set_option(tcp::no_delay(true), e2);
            p->server.set_option(tcp::no_delay(true), e2);
            read(p, p->up);
            read(p, p->down);
          });
        }
      }
      accept();
    });
  }

  size_t next_read_size(const Pipe& pipe) const {
    if (pipe.handshake_stage == 0) return kHelloSize;
    if (pipe.handshake_stage == 1) return kProofSize;
    return kRecordHeaderSize;
  }

  void read(const PairPtr& p, Pipe& pipe) {
    if (pipe.raw) {
      pipe.buffer.resize(4096);
      pipe.from.async_read_some(asio::buffer(pipe.buffer), [this, p, &pipe](std::error_code e, size_t n) {
        if (e || p->closed) return close(p);
        enqueue(p, pipe, std::vector<uint8_t>(pipe.buffer.begin(), pipe.buffer.begin() + long(n)), false);
        read(p, pipe);
      });
      return;
    }
    pipe.buffer.resize(next_read_size(pipe));
    asio::async_read(pipe.from, asio::buffer(pipe.buffer), [this, p, &pipe](std::error_code e, size_t) {
      if (e || p->closed) return close(p);
      if (pipe.handshake_stage < 2) {
        ++pipe.handshake_stage;
        enqueue(p, pipe, pipe.buffer, false);
        return read(p, pipe);
      }
      uint32_t length = 0;
      std::memcpy(&length, pipe.buffer.data(), 4);
      if (length > kMaxRecordCiphertext) {
        pipe.raw = true;
        enqueue(p, pipe, pipe.buffer, false);
        return read(p, pipe);
      }
      auto record = std::make_shared<std::vector<uint8_t>>(pipe.buffer);
      record->resize(kRecordHeaderSize + length);
      asio::async_read(pipe.from, asio::buffer(record->data() + kRecordHeaderSize, length),
                       [this, p, &pipe, record](std::error_code e2, size_t) {
                         if (e2 || p->closed) return close(p);
                         enqueue(p, pipe, std::move(*record), true);
                         read(p, pipe);
                       });
    });
  }

  void enqueue(const PairPtr& p, Pipe& pipe, std::vector<uint8_t> bytes, bool is_record) {
    if (blackhole) {
      p->swallowed = true;
      std::lock_guard lock(mutex);
      counts.bytes_swallowed += bytes.size();
      return;
    }
    if (is_record && rewrite_length && &pipe == &p->up) {
      std::memcpy(bytes.data(), &*rewrite_length, 4);
      rewrite_length.reset();
      std::lock_guard lock(mutex);
      ++counts.lengths_rewritten;
    }
    if (is_record && delete_length && &pipe == &p->up && bytes.size() == kRecordHeaderSize + *delete_length) {
      delete_length.reset();
      std::lock_guard lock(mutex);
      ++counts.records_deleted;
      return;
    }
    // TCP loses nothing it delivers: a lost segment is sent again (a delay), or the connection
    // dies. Only the second is simulated: a lost record cuts the link where it was lost; what
    // came before it still arrives.
    const bool lost = is_record && options.loss > 0 && std::uniform_real_distribution<double>(0, 1)(random) < options.loss;
    if (is_record && !lost) {
      std::lock_guard lock(mutex);
      ++counts.records_forwarded;
    }
    auto extra = std::chrono::microseconds(0);
    if (options.jitter.count() > 0)
      extra = std::chrono::microseconds(std::uniform_int_distribution<int64_t>(0, options.jitter.count())(random));
    auto release = std::max(pipe.last_release, Clock::now() + options.delay + extra);
    if (options.bytes_per_second > 0)
      release += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(double(bytes.size()) / options.bytes_per_second));
    pipe.last_release = release;
    if (lost) bytes.clear();
    pipe.queue.push_back({release, std::move(bytes), lost});
    drain(p, pipe);
  }

  void drain(const PairPtr& p, Pipe& pipe) {
    if (pipe.writing || pipe.waiting || pipe.queue.empty() || p->closed) return;
    if (pipe.queue.front().release > Clock::now()) {
      pipe.waiting = true;
      pipe.timer.expires_at(pipe.queue.front().release);
      pipe.timer.async_wait([this, p, &pipe](std::error_code) {
        pipe.waiting = false;
        drain(p, pipe);
      });
      return;
    }
    if (pipe.queue.front().cut) {
      {
        std::lock_guard lock(mutex);
        ++counts.records_dropped;
      }
      return close(p);
    }
    pipe.writing = true;
    asio::async_write(pipe.to, asio::buffer(pipe.queue.front().bytes), [this, p, &pipe](std::error_code e, size_t) {
      pipe.writing = false;
      if (e || p->closed) return close(p);
      pipe.queue.pop_front();
      drain(p, pipe);
    });
  }

  void disconnect() {
    const size_t n = pairs.size();
    for (auto p : std::vector<PairPtr>(pairs.begin(), pairs.end())) close(p);
    std::lock_guard lock(mutex);
    counts.disconnects += n;
  }

  void garbage(size_t bytes) {
    std::vector<uint8_t> noise(bytes);
    for (auto& b : noise) b = uint8_t(random());
    for (const auto& p : pairs) {
      enqueue(p, p->up, noise, false);
      std::lock_guard lock(mutex);
      ++counts.garbage_injections;
      counts.garbage_bytes += bytes;
    }
  }
};

FaultProxy::FaultProxy(std::string target_host, uint16_t target_port, FaultOptions options)
    : impl_(std::make_unique<Impl>(std::move(target_host), target_port, options)) {}

FaultProxy::~FaultProxy() { stop(); }

void FaultProxy::start() {
  Impl& s = *impl_;
  if (s.thread.joinable()) return;
  const tcp::endpoint endpoint(asio::ip::make_address("127.0.0.1"), 0);
  s.acceptor.open(endpoint.protocol());
  s.acceptor.bind(endpoint);
  s.acceptor.listen();
  s.bound_port = s.acceptor.local_endpoint().port();
  s.accept();
  if (s.options.disconnect_after) {
    s.trigger_disconnect.expires_after(*s.options.disconnect_after);
    s.trigger_disconnect.async_wait([&s](std::error_code e) {
      if (!e && !s.closing) s.disconnect();
    });
  }
  if (s.options.garbage_after) {
    s.trigger_garbage.expires_after(*s.options.garbage_after);
    s.trigger_garbage.async_wait([&s](std::error_code e) {
      if (!e && !s.closing) s.garbage(s.options.garbage_bytes);
    });
  }
  s.work.emplace(s.io.get_executor());
  s.thread = std::thread([&s] { s.io.run(); });
}

void FaultProxy::stop() {
  Impl& s = *impl_;
  if (!s.thread.joinable()) return;
  asio::post(s.io, [&s] {
    s.closing = true;
    std::error_code ignored;
    s.acceptor.close(ignored);
    s.trigger_disconnect.cancel();
    s.trigger_garbage.cancel();
    for (auto p : std::vector<PairPtr>(s.pairs.begin(), s.pairs.end())) s.close(p);
  });
  s.work.reset();
  s.thread.join();
}

uint16_t FaultProxy::port() const { return impl_->bound_port; }

void FaultProxy::disconnect_now() {
  asio::post(impl_->io, [this] { impl_->disconnect(); });
}

void FaultProxy::inject_garbage_now(size_t bytes) {
  asio::post(impl_->io, [this, bytes] { impl_->garbage(bytes); });
}

void FaultProxy::rewrite_next_record_length(uint32_t new_length) {
  asio::post(impl_->io, [this, new_length] { impl_->rewrite_length = new_length; });
}

void FaultProxy::delete_next_record(uint32_t ciphertext_length) {
  asio::post(impl_->io, [this, ciphertext_length] { impl_->delete_length = ciphertext_length; });
}

void FaultProxy::set_blackhole(bool on) {
  asio::post(impl_->io, [this, on] {
    impl_->blackhole = on;
    // TCP never skips bytes: a connection that lost some to the outage cannot simply go on, so
    // when the link comes back it is cut (as a real one would die of its unanswered segments),
    // and the sessions rebuild it at once instead of waiting out their handshake timeouts.
    if (!on)
      for (auto p : std::vector<PairPtr>(impl_->pairs.begin(), impl_->pairs.end()))
        if (p->swallowed) impl_->close(p);
  });
}

FaultCounts FaultProxy::counts() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->counts;
}

}  // namespace rt::net
