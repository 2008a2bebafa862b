// Keys, handshake and sealed records (libsodium), without sockets: right and wrong key, forward
// secrecy (the traffic keys need an ephemeral secret, not K alone), reflected and tampered hellos,
// the listener proving nothing before the connector has, tampered ciphertext and headers, records
// deleted, replayed or reordered; a proof reflected back to its sender.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <sodium.h>

#include <filesystem>
#include <fstream>

#include "net/message_codec.h"
#include "net/secure_channel.h"

using namespace rt::net;

namespace {

struct Pair {
  Handshake connector, listener;
  Pair(const SessionKey& a, const SessionKey& b) : connector(a, Role::Connector), listener(b, Role::Listener) {}
  Pair(const SessionKey& key, const std::array<uint8_t, 32>& connector_nonce, const std::array<uint8_t, 32>& listener_nonce)
      : connector(key, Role::Connector, connector_nonce), listener(key, Role::Listener, listener_nonce) {}
  // Both hellos; the connector's proof, checked by the listener; then the listener's proof (or,
  // having refused, its decoy), checked by the connector. Returns {connector's verdict,
  // listener's verdict}.
  std::pair<std::optional<std::string>, std::optional<std::string>> run() {
    REQUIRE_FALSE(connector.receive_hello(listener.hello()));
    REQUIRE_FALSE(listener.receive_hello(connector.hello()));
    auto at_listener = listener.verify_proof(connector.proof());
    const auto reply = at_listener ? Handshake::decoy_proof() : listener.proof();
    return {connector.verify_proof(reply), at_listener};
  }
};

std::array<uint8_t, 32> hash(const std::array<uint8_t, 32>* key, std::initializer_list<std::span<const uint8_t>> parts) {
  crypto_generichash_state state;
  crypto_generichash_init(&state, key ? key->data() : nullptr, key ? 32 : 0, 32);
  for (auto part : parts) crypto_generichash_update(&state, part.data(), part.size());
  std::array<uint8_t, 32> out{};
  crypto_generichash_final(&state, out.data(), 32);
  return out;
}
std::span<const uint8_t> text(const char* label) { return {reinterpret_cast<const uint8_t*>(label), std::strlen(label)}; }

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
  // Fresh nonces and ephemeral keys: a second handshake with the same key gives other traffic keys.
  Pair again(key, key);
  again.run();
  CHECK(again.connector.keys().send != c.send);
  // Once taken, the secrets are wiped: no more keys, but the handshake stays complete.
  pair.connector.wipe();
  CHECK(pair.connector.complete());
  CHECK_THROWS(pair.connector.keys());
}

TEST_CASE("forward secrecy: the traffic keys need an ephemeral secret, not K and the transcript alone") {
  const SessionKey key = random_session_key();
  std::array<uint8_t, 32> nonce_c{}, nonce_l{};
  nonce_c.fill(7), nonce_l.fill(9);
  // The same K and the same nonces twice: other ephemeral keys, so other traffic keys.
  Pair first(key, nonce_c, nonce_l), second(key, nonce_c, nonce_l);
  REQUIRE_FALSE(first.run().first);
  REQUIRE_FALSE(second.run().first);
  const auto hello_c = first.connector.hello(), hello_l = first.listener.hello();
  CHECK(std::equal(hello_c.begin() + 8, hello_c.begin() + 40, second.connector.hello().begin() + 8));  // same nonce
  const TrafficKeys keys = first.connector.keys();
  CHECK(keys.send != second.connector.keys().send);
  CHECK(keys.receive != second.connector.keys().receive);

  // Someone who recorded both hellos and later learns K: what version 1 derived from them, and
  // other ways of hashing K with the whole transcript, are none of the keys.
  const auto h = Handshake::transcript_hash(hello_c, hello_l);
  const auto nc = std::span(hello_c).subspan(8, 32), nl = std::span(hello_l).subspan(8, 32);
  const auto k_and_h = hash(&key.bytes, {text("RemoteTouch/2 secret"), h});
  const std::vector<std::array<uint8_t, 32>> guesses = {
      hash(&key.bytes, {text("RemoteTouch/1 key connector->listener"), nc, nl}),
      hash(&key.bytes, {text("RemoteTouch/1 key listener->connector"), nc, nl}),
      k_and_h,
      hash(&k_and_h, {text("RemoteTouch/2 key connector->listener")}),
      hash(&k_and_h, {text("RemoteTouch/2 key listener->connector")}),
      hash(&key.bytes, {text("RemoteTouch/2 key connector->listener"), hello_c, hello_l}),
  };
  for (const auto& guess : guesses) {
    CHECK(guess != keys.send);
    CHECK(guess != keys.receive);
  }
  // Playing either side again with K, the recorded nonce and the other side's recorded hello
  // gives other keys too: the ephemeral secret behind the recorded hello is gone.
  Handshake replay(key, Role::Connector, nonce_c);
  REQUIRE_FALSE(replay.receive_hello(hello_l));
  CHECK(replay.hello() != hello_c);
  // Its proof is not the recorded one: the recorded listener would refuse it.
  Handshake recorded_listener_stand_in(key, Role::Listener, nonce_l);
  REQUIRE_FALSE(recorded_listener_stand_in.receive_hello(hello_c));
  CHECK(recorded_listener_stand_in.verify_proof(replay.proof()));
}

TEST_CASE("the listener proves the key only after the connector has") {
  const SessionKey key = random_session_key();
  Handshake connector(key, Role::Connector), listener(key, Role::Listener);
  REQUIRE_FALSE(connector.receive_hello(listener.hello()));
  REQUIRE_FALSE(listener.receive_hello(connector.hello()));
  CHECK_THROWS_WITH(listener.proof(), Catch::Contains("only after the connector"));
  auto wrong = connector.proof();
  wrong[0] ^= 1;
  CHECK(listener.verify_proof(wrong));
  CHECK_THROWS(listener.proof());  // still nothing after a wrong proof
  // What it sends instead proves nothing: the connector, holding the right key, refuses it.
  CHECK_THAT(*connector.verify_proof(Handshake::decoy_proof()), Catch::Contains("did not prove knowledge"));
}

TEST_CASE("a proof reflected back to its sender is refused: each side proves its own role") {
  // Someone in the middle who knows no key sends the connector its own proof back. Were the two
  // roles' proofs the same, that would pass for the listener's proof of the key.
  const SessionKey key = random_session_key();
  Handshake connector(key, Role::Connector), listener(key, Role::Listener);
  REQUIRE_FALSE(connector.receive_hello(listener.hello()));
  REQUIRE_FALSE(listener.receive_hello(connector.hello()));
  const auto own = connector.proof();
  const auto reflected = connector.verify_proof(own);
  REQUIRE(reflected);
  CHECK_THAT(*reflected, Catch::Contains("did not prove knowledge"));
  CHECK_THROWS(connector.keys());
  // The same exchange played honestly verifies on both sides: only the reflection was refused.
  REQUIRE_FALSE(listener.verify_proof(own));
  const auto listener_proof = listener.proof();
  CHECK(listener_proof != own);
  CHECK_FALSE(connector.verify_proof(listener_proof));
}

TEST_CASE("a weak session key is refused before any handshake") {
  SessionKey zero;
  CHECK(is_weak_session_key(zero));
  CHECK_FALSE(is_weak_session_key(random_session_key()));
  CHECK_THROWS_WITH(Handshake(zero, Role::Connector), Catch::Contains("weak session key"));
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

TEST_CASE("bad hellos: wrong magic, another version, reserved byte, reflected, wrong size, weak ephemeral key") {
  const SessionKey key = random_session_key();
  const auto good = Handshake(key, Role::Connector).hello();
  auto refusal = [&](std::span<const uint8_t> hello) {
    Handshake listener(key, Role::Listener);
    auto error = listener.receive_hello(hello);
    CHECK_THROWS(listener.proof());  // no proof after a refused hello
    return error.value_or("accepted");
  };
  auto tampered = [&](size_t at, uint8_t value) {
    auto hello = good;
    hello[at] = value;
    return refusal(hello);
  };
  CHECK_THAT(tampered(0, 'X'), Catch::Contains("bad hello magic"));
  CHECK_THAT(tampered(4, 1), Catch::Contains("peer speaks protocol version 1, this build version 2"));
  CHECK_THAT(tampered(5, 1), Catch::Contains("version 258"));
  CHECK_THAT(tampered(7, 1), Catch::Contains("reserved byte is 1"));
  CHECK_THAT(tampered(6, uint8_t(Role::Listener)), Catch::Contains("wrong role"));
  CHECK_THAT(refusal(std::vector<uint8_t>(12)), Catch::Contains("12 bytes"));
  {
    Handshake listener(key, Role::Listener);
    auto reflected = listener.hello();
    reflected[6] = uint8_t(Role::Connector);
    CHECK_THAT(*listener.receive_hello(reflected), Catch::Contains("reflected"));
  }
  // The prefix alone says the same, before the rest of a hello is awaited: a version 1 peer's
  // hello is 40 bytes, not 72.
  auto old = good;
  old[4] = 1;
  CHECK_THAT(*Handshake::check_hello_prefix(std::span(old).first(kHelloPrefixSize), Role::Listener),
             Catch::Contains("version 1"));
  CHECK_FALSE(Handshake::check_hello_prefix(std::span(good).first(kHelloPrefixSize), Role::Listener));
  CHECK(Handshake::has_hello_magic(std::span(old).first(kHelloPrefixSize)));
  const std::array<uint8_t, kHelloPrefixSize> garbage_prefix{'G', 'E', 'T', ' ', '/', ' ', 'H', 'T'};
  CHECK_FALSE(Handshake::has_hello_magic(garbage_prefix));
  // A low-order ephemeral key (the identity here) would make the shared secret public.
  auto weak = good;
  std::fill(weak.begin() + 40, weak.end(), 0);
  CHECK_THAT(refusal(weak), Catch::Contains("weak (low-order) point"));
  weak[40] = 1;
  CHECK_THAT(refusal(weak), Catch::Contains("weak (low-order) point"));
}

TEST_CASE("the transcript covers every byte of both hellos; tampering in transit fails the handshake on both sides") {
  const SessionKey key = random_session_key();
  const auto hello_c = Handshake(key, Role::Connector).hello(), hello_l = Handshake(key, Role::Listener).hello();
  const auto h = Handshake::transcript_hash(hello_c, hello_l);
  for (size_t i = 0; i < kHelloSize; ++i) {
    auto c = hello_c, l = hello_l;
    c[i] ^= 0x10;
    l[i] ^= 0x10;
    CHECK(Handshake::transcript_hash(c, hello_l) != h);
    CHECK(Handshake::transcript_hash(hello_c, l) != h);
  }
  CHECK(Handshake::transcript_hash(hello_l, hello_c) != h);  // order counts
  // A nonce or ephemeral-key byte changed on the way passes the hello's checks, but the two
  // sides then hold different transcripts (and shared secrets): neither proof verifies.
  for (const size_t at : {size_t(8), size_t(39), size_t(40), size_t(71)}) {
    Handshake connector(key, Role::Connector), listener(key, Role::Listener);
    auto in_transit = connector.hello();
    in_transit[at] ^= 0x01;
    REQUIRE_FALSE(connector.receive_hello(listener.hello()));
    const auto accepted = listener.receive_hello(in_transit);
    if (accepted) {  // a flipped bit can land on a low-order point
      CHECK_THAT(*accepted, Catch::Contains("weak"));
      continue;
    }
    CHECK(listener.verify_proof(connector.proof()));
    CHECK(connector.verify_proof(Handshake::decoy_proof()));
  }
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

  SECTION("the same record again is out of sequence (a replay)") {
    CHECK(open(first, &plaintext, &reason) == RecordError::OutOfSequence);
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
  SECTION("counters must be consecutive: a gap (a deleted record) is refused") {
    std::vector<std::vector<uint8_t>> records;
    for (int counter = 2; counter <= 10; ++counter) records.push_back(sealer.seal(message));
    REQUIRE(open(records[0], &plaintext, &reason) == RecordError::None);  // counter 2
    CHECK(open(records[8], &plaintext, &reason) == RecordError::OutOfSequence);  // counter 10
    CHECK_THAT(reason, Catch::Contains("record 10 out of sequence after 2 (7 deleted on the way)"));
    CHECK(plaintext.empty());
    CHECK(opener.last_counter() == 2);  // nothing accepted
    REQUIRE(open(records[1], &plaintext, &reason) == RecordError::None);  // 3 is still the next
  }
  SECTION("going back is refused") {
    const auto second = sealer.seal(message);
    const auto third = sealer.seal(message);
    REQUIRE(open(second, &plaintext, &reason) == RecordError::None);
    REQUIRE(open(third, &plaintext, &reason) == RecordError::None);
    CHECK(open(second, &plaintext, &reason) == RecordError::OutOfSequence);
    CHECK_THAT(reason, Catch::Contains("replayed or reordered"));
  }
  SECTION("reordered: the later one first is a gap") {
    const auto second = sealer.seal(message);
    const auto third = sealer.seal(message);
    CHECK(open(third, &plaintext, &reason) == RecordError::OutOfSequence);
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
