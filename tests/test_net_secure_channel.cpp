// Keys, handshake and sealed records (libsodium), without sockets: right and wrong key, reflected
// hellos, tampered ciphertext and headers, replayed and missing records.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "net/message_codec.h"
#include "net/secure_channel.h"

using namespace rt::net;

namespace {

struct Pair {
  Handshake connector, listener;
  Pair(const SessionKey& a, const SessionKey& b) : connector(a, Role::Connector), listener(b, Role::Listener) {}
  // Both hellos, then both proofs; returns {connector's verdict, listener's verdict}.
  std::pair<std::optional<std::string>, std::optional<std::string>> run() {
    REQUIRE_FALSE(connector.receive_hello(listener.hello()));
    REQUIRE_FALSE(listener.receive_hello(connector.hello()));
    return {connector.verify_proof(listener.proof()), listener.verify_proof(connector.proof())};
  }
};

}  // namespace

TEST_CASE("session keys from hex and key files, with clear errors") {
  const SessionKey key = random_session_key();
  CHECK(session_key_from_hex(to_hex(key)).bytes == key.bytes);
  CHECK(session_key_from_hex("  " + to_hex(key) + "\n").bytes == key.bytes);
  CHECK_THROWS_WITH(session_key_from_hex("abcd"), Catch::Contains("64 hex digits") && Catch::Contains("got 4"));
  CHECK_THROWS_WITH(session_key_from_hex(std::string(63, '0') + "g"), Catch::Contains("'g' is not a hex digit"));
  const auto dir = std::filesystem::temp_directory_path() / ("rt_net_key_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto owner_only = [](const std::filesystem::path& path) {
    std::filesystem::permissions(path, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  };
  std::ofstream(dir / "good.key") << to_hex(key) << "\n";
  owner_only(dir / "good.key");
  CHECK(load_session_key_file(dir / "good.key").bytes == key.bytes);
  std::ofstream(dir / "bad.key") << "not a key\n";
  owner_only(dir / "bad.key");
  CHECK_THROWS_WITH(load_session_key_file(dir / "bad.key"), Catch::Contains("bad.key") && Catch::Contains("64 hex"));
  CHECK_THROWS_WITH(load_session_key_file(dir / "missing.key"), Catch::Contains("cannot be opened"));

  // A key others can read is refused, saying how to fix it.
  std::filesystem::permissions(dir / "good.key", std::filesystem::perms::group_read | std::filesystem::perms::others_read,
                               std::filesystem::perm_options::add);
  CHECK_THROWS_WITH(load_session_key_file(dir / "good.key"), Catch::Contains("open to the group or others (mode 0644)") &&
                                                                 Catch::Contains("chmod 600"));
  // Not a regular file: a device that never ends, a folder, a FIFO (without blocking).
  CHECK_THROWS_WITH(load_session_key_file("/dev/zero"), Catch::Contains("/dev/zero is not a regular file"));
  CHECK_THROWS_WITH(load_session_key_file(dir), Catch::Contains("is not a regular file"));
  REQUIRE(::mkfifo((dir / "fifo.key").c_str(), 0600) == 0);
  CHECK_THROWS_WITH(load_session_key_file(dir / "fifo.key"), Catch::Contains("fifo.key is not a regular file"));
  // Longer than a key's line, and weak keys.
  std::ofstream(dir / "long.key") << to_hex(key) << std::string(1000, ' ') << "\n";
  owner_only(dir / "long.key");
  CHECK_THROWS_WITH(load_session_key_file(dir / "long.key"), Catch::Contains("longer than a key's line"));
  for (const char* weak : {"0000000000000000000000000000000000000000000000000000000000000000",
                           "abababababababababababababababababababababababababababababababab"}) {
    std::ofstream(dir / "weak.key") << weak << "\n";
    owner_only(dir / "weak.key");
    CHECK_THROWS_WITH(load_session_key_file(dir / "weak.key"), Catch::Contains("weak key") && Catch::Contains("keygen"));
  }
}

TEST_CASE("a new key file: owner-only, never over an existing file or through a link") {
  const auto dir = std::filesystem::temp_directory_path() / ("rt_net_keygen_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const SessionKey key = write_new_session_key_file(dir / "new.key");
  CHECK(load_session_key_file(dir / "new.key").bytes == key.bytes);
  const auto perms = std::filesystem::status(dir / "new.key").permissions();
  CHECK(perms == (std::filesystem::perms::owner_read | std::filesystem::perms::owner_write));
  CHECK_THROWS_WITH(write_new_session_key_file(dir / "new.key"), Catch::Contains("never overwritten"));
  CHECK(load_session_key_file(dir / "new.key").bytes == key.bytes);  // the old key is still there
  std::filesystem::create_symlink(dir / "elsewhere.key", dir / "link.key");
  CHECK_THROWS(write_new_session_key_file(dir / "link.key"));
  CHECK_FALSE(std::filesystem::exists(dir / "elsewhere.key"));  // nothing written through the link
  CHECK(write_new_session_key_file(dir / "other.key").bytes != key.bytes);
  std::filesystem::remove_all(dir);
}

TEST_CASE("handshake with the same key: both verify and derive crosswise traffic keys") {
  const SessionKey key = random_session_key();
  Pair pair(key, key);
  const auto [connector, listener] = pair.run();
  CHECK_FALSE(connector);
  CHECK_FALSE(listener);
  const TrafficKeys c = pair.connector.keys(), l = pair.listener.keys();
  CHECK(c.send == l.receive);
  CHECK(c.receive == l.send);
  CHECK(c.send != c.receive);
  // Fresh nonces: a second handshake with the same key gives other traffic keys.
  Pair again(key, key);
  again.run();
  CHECK(again.connector.keys().send != c.send);
}

TEST_CASE("handshake with a wrong key is refused on both sides") {
  Pair pair(random_session_key(), random_session_key());
  const auto [connector, listener] = pair.run();
  REQUIRE(connector);
  REQUIRE(listener);
  CHECK_THAT(*connector, Catch::Contains("did not prove knowledge of the session key"));
  CHECK_THAT(*listener, Catch::Contains("did not prove knowledge of the session key"));
  CHECK_THROWS(pair.connector.keys());
}

TEST_CASE("bad hellos: wrong magic, reflected hello, wrong size") {
  const SessionKey key = random_session_key();
  Handshake listener(key, Role::Listener);
  auto hello = Handshake(key, Role::Connector).hello();
  hello[0] = 'X';
  CHECK_THAT(*listener.receive_hello(hello), Catch::Contains("bad hello magic"));
  CHECK_THAT(*listener.receive_hello(listener.hello()), Catch::Contains("wrong role"));
  CHECK_THAT(*listener.receive_hello(std::vector<uint8_t>(12)), Catch::Contains("12 bytes"));
  CHECK_THROWS(listener.proof());  // no proof before a valid hello
}

TEST_CASE("records: round trip, tampering, replay, gaps, oversize") {
  const SessionKey key = random_session_key();
  Pair pair(key, key);
  pair.run();
  RecordSealer sealer(pair.connector.keys().send);
  RecordOpener opener(pair.listener.keys().receive, kMaxMessageSize);
  auto open = [&](const std::vector<uint8_t>& record, std::vector<uint8_t>* plaintext, std::string* reason) {
    return opener.open(std::span(record).first(kRecordHeaderSize), std::span(record).subspan(kRecordHeaderSize), plaintext,
                       reason);
  };
  const std::vector<uint8_t> message = encode_message(HeartbeatMessage{1, 2});
  std::vector<uint8_t> plaintext;
  std::string reason;

  const auto first = sealer.seal(message);
  CHECK(first.size() == kRecordHeaderSize + message.size() + kRecordTagSize);
  REQUIRE(open(first, &plaintext, &reason) == RecordError::None);
  CHECK(plaintext == message);

  SECTION("the same record again is a replay") {
    CHECK(open(first, &plaintext, &reason) == RecordError::Replay);
    CHECK_THAT(reason, Catch::Contains("replayed"));
    CHECK(plaintext.empty());
  }
  SECTION("a tampered ciphertext byte fails authentication") {
    auto record = sealer.seal(message);
    record[kRecordHeaderSize + 3] ^= 1;
    CHECK(open(record, &plaintext, &reason) == RecordError::AuthFailed);
    CHECK_THAT(reason, Catch::Contains("failed authentication"));
  }
  SECTION("a tampered counter fails authentication (the header is authenticated)") {
    auto record = sealer.seal(message);
    record[4] ^= 2;
    CHECK(open(record, &plaintext, &reason) == RecordError::AuthFailed);
  }
  SECTION("the other direction's key does not open it") {
    RecordOpener wrong(pair.listener.keys().send, kMaxMessageSize);
    auto record = sealer.seal(message);
    CHECK(wrong.open(std::span(record).first(kRecordHeaderSize), std::span(record).subspan(kRecordHeaderSize), &plaintext,
                     &reason) == RecordError::AuthFailed);
  }
  SECTION("a skipped record counts as missing, an older one after it as a replay") {
    const auto second = sealer.seal(message);
    const auto third = sealer.seal(message);
    REQUIRE(open(third, &plaintext, &reason) == RecordError::None);
    CHECK(opener.records_missing() == 1);
    CHECK(open(second, &plaintext, &reason) == RecordError::Replay);
  }
  SECTION("a length over the limit means the stream is out of step") {
    auto record = sealer.seal(message);
    const uint32_t huge = uint32_t(kMaxMessageSize + kRecordTagSize + 1);
    std::memcpy(record.data(), &huge, 4);
    RecordHeader header;
    CHECK(opener.check_header(std::span(record).first(kRecordHeaderSize), &header, &reason) == RecordError::Oversize);
    CHECK_THAT(reason, Catch::Contains("out of step"));
  }
}
