// Keys, handshake and sealed records (libsodium), without sockets: right and wrong key, forward
// secrecy (the traffic keys need an ephemeral secret, not K alone), reflected and tampered hellos,
// the listener proving nothing before the connector has, tampered ciphertext and headers, records
// deleted, replayed or reordered; a proof reflected back to its sender.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <sodium.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <new>
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
  // The error names where, never what: the rest of the text may be most of a key.
  const std::string one_wrong = to_hex(key).substr(0, 63) + "g";
  CHECK_THROWS_WITH(session_key_from_hex(one_wrong), Catch::Contains("character 64 of 64 is not a hex digit") &&
                                                         !Catch::Contains("'g'") && !Catch::Contains(one_wrong.substr(0, 8)));
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
  // A key file with one character wrong: its error quotes nothing of the file.
  const std::string almost = "9f" + to_hex(key).substr(2, 61) + "z";
  std::ofstream(dir / "almost.key") << almost << "\n";
  owner_only(dir / "almost.key");
  CHECK_THROWS_WITH(load_session_key_file(dir / "almost.key"),
                    Catch::Contains("almost.key") && Catch::Contains("character 64 of 64 is not a hex digit") &&
                        !Catch::Contains("'z'") && !Catch::Contains(almost.substr(0, 12)) && !Catch::Contains(almost.substr(40, 12)));
  CHECK_THROWS_WITH(load_session_key_file(dir / "missing.key"), Catch::Contains("cannot be opened"));

  // A key others can read is refused, saying how to fix it.
  std::filesystem::permissions(dir / "good.key", std::filesystem::perms::group_read | std::filesystem::perms::others_read,
                               std::filesystem::perm_options::add);
  CHECK_THROWS_WITH(load_session_key_file(dir / "good.key"), Catch::Contains("open to the group or others (mode 0644)") &&
                                                                 Catch::Contains("chmod 600"));
  // Before anything is read: a file others can read is refused whatever it holds, a long one too.
  std::ofstream(dir / "open_long.key") << std::string(1000, 'x') << "\n";
  std::filesystem::permissions(dir / "open_long.key", std::filesystem::perms::owner_read | std::filesystem::perms::others_read);
  CHECK_THROWS_WITH(load_session_key_file(dir / "open_long.key"), Catch::Contains("open to the group or others (mode 0404)"));
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
                           "abababababababababababababababababababababababababababababababab",
                           // Hand-typed: a padded number, a pattern, a count.
                           "0000000000000000000000000000000000000000000000000000000000000042",
                           "0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef",
                           "deadbeefcafebabedeadbeefcafebabedeadbeefcafebabedeadbeefcafebabe",
                           "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f"}) {
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
  // Random keys pass (the bound is far from what random bytes give: about 30 values and steps).
  for (int i = 0; i < 10000; ++i) REQUIRE_FALSE(is_weak_session_key(random_session_key()));
  CHECK_THROWS_WITH(Handshake(zero, Role::Connector), Catch::Contains("weak session key"));
}

TEST_CASE("handshake with a wrong key is refused on both sides, at the hello") {
  Pair pair(random_session_key(), random_session_key());
  CHECK_THAT(*pair.listener.receive_hello(pair.connector.hello()), Catch::Contains("not authenticated with our session key"));
  CHECK_THAT(*pair.connector.receive_hello(pair.listener.hello()), Catch::Contains("not authenticated with our session key"));
  CHECK_THROWS(pair.listener.proof());
  CHECK_THROWS(pair.connector.keys());
}

TEST_CASE("the hello gate: a MAC of the key over every byte, then a timestamp later than the last accepted") {
  const SessionKey key = random_session_key();
  HelloGate gate(key);
  const auto first = Handshake(key, Role::Connector).hello();
  const auto second = Handshake(key, Role::Connector).hello();
  CHECK(hello_timestamp(second) > hello_timestamp(first));
  // Any byte changed, the MAC's too, and the hello is not authentic; nor is one of another key.
  for (size_t i = 0; i < kHelloSize; ++i) {
    auto tampered = first;
    tampered[i] ^= 0x04;
    CHECK(gate.check(tampered) == HelloVerdict::NotAuthentic);
  }
  CHECK(gate.check(Handshake(random_session_key(), Role::Connector).hello()) == HelloVerdict::NotAuthentic);
  CHECK(gate.check(std::span(first).first(kHelloSize - 1)) == HelloVerdict::NotAuthentic);
  CHECK(gate.last_accepted() == 0);
  // The genuine hello once; played again it is a replay, and so is an older genuine one.
  CHECK(gate.check(second) == HelloVerdict::Accepted);
  CHECK(gate.check(second) == HelloVerdict::Replayed);
  CHECK(gate.check(first) == HelloVerdict::Replayed);
  CHECK(gate.check(Handshake(key, Role::Connector).hello()) == HelloVerdict::Accepted);
  // Genuine, but stamped before the last one accepted (recorded earlier, or a clock set back).
  CHECK(gate.check(Handshake(key, Role::Connector, gate.last_accepted() - 1).hello()) == HelloVerdict::Replayed);
  CHECK(gate.check(Handshake(key, Role::Connector, gate.last_accepted() + 1).hello()) == HelloVerdict::Accepted);
  // The MAC key is derived from K (crypto_kdf), not K itself.
  std::array<uint8_t, kHelloMacSize> with_k{};
  crypto_auth(with_k.data(), first.data(), kHelloMacAt, key.bytes.data());
  CHECK(!std::equal(with_k.begin(), with_k.end(), first.begin() + kHelloMacAt));
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
  CHECK_THAT(tampered(4, 2), Catch::Contains("peer speaks protocol version 2, this build version 3"));
  CHECK_THAT(tampered(5, 1), Catch::Contains("version 259"));
  CHECK_THAT(tampered(7, 1), Catch::Contains("reserved byte is 1"));
  CHECK_THAT(tampered(6, uint8_t(Role::Listener)), Catch::Contains("wrong role"));
  CHECK_THAT(refusal(std::vector<uint8_t>(12)), Catch::Contains("12 bytes"));
  // Tampered after the prefix: the MAC no longer holds.
  CHECK_THAT(tampered(20, uint8_t(good[20] ^ 1)), Catch::Contains("not authenticated with our session key"));
  CHECK_THAT(tampered(kHelloSize - 1, uint8_t(good[kHelloSize - 1] ^ 1)), Catch::Contains("not authenticated"));
  const HelloAuthenticator authenticator(key);
  {
    Handshake listener(key, Role::Listener);
    auto reflected = listener.hello();
    reflected[6] = uint8_t(Role::Connector);
    authenticator.sign(reflected);  // whoever holds the key could
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
  std::fill(weak.begin() + 40, weak.begin() + 72, 0);
  authenticator.sign(weak);
  CHECK_THAT(refusal(weak), Catch::Contains("weak (low-order) point"));
  weak[40] = 1;
  authenticator.sign(weak);
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
  // A nonce or ephemeral-key byte changed on the way by someone holding the key (who can sign
  // it again) passes the hello's checks, but the two sides then hold different transcripts (and
  // shared secrets): neither proof verifies. Without the key the MAC refuses it first.
  const HelloAuthenticator authenticator(key);
  for (const size_t at : {size_t(8), size_t(39), size_t(40), size_t(71)}) {
    Handshake connector(key, Role::Connector), listener(key, Role::Listener);
    auto in_transit = connector.hello();
    in_transit[at] ^= 0x01;
    {
      Handshake unsigned_listener(key, Role::Listener);
      CHECK_THAT(*unsigned_listener.receive_hello(in_transit), Catch::Contains("not authenticated"));
    }
    authenticator.sign(in_transit);
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
  // Each record carries the final flag inside its sealed part.
  auto open = [&](const std::vector<uint8_t>& record, std::vector<uint8_t>* plaintext, std::string* reason) {
    return opener.open(std::span(record).first(kRecordHeaderSize), std::span(record).subspan(kRecordHeaderSize), plaintext,
                       reason);
  };
  const std::vector<uint8_t> message = encode_message(HeartbeatMessage{1, 2});
  std::vector<uint8_t> plaintext;
  std::string reason;

  const auto first = sealer.seal(message);
  CHECK(first.size() == kRecordHeaderSize + kRecordFlagSize + message.size() + kRecordTagSize);
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
    // One byte over one record's bound, not a message's: the length is not authenticated yet.
    const uint32_t huge = uint32_t(kMaxRecordCiphertext + 1);
    std::memcpy(record.data(), &huge, 4);
    RecordHeader header;
    CHECK(opener.check_header(std::span(record).first(kRecordHeaderSize), &header, &reason) == RecordError::Oversize);
    CHECK_THAT(reason, Catch::Contains("out of step"));
    const uint32_t most = uint32_t(kMaxRecordCiphertext);
    std::memcpy(record.data(), &most, 4);
    CHECK(opener.check_header(std::span(record).first(kRecordHeaderSize), &header, &reason) == RecordError::None);
  }
}

TEST_CASE("a message larger than a record goes in records of at most 64 KiB, and comes back whole") {
  const SessionKey key = random_session_key();
  Pair pair(key, key);
  pair.run();
  RecordSealer sealer(pair.connector.keys().send);
  RecordOpener opener(pair.listener.keys().receive, 200'000);
  std::vector<uint8_t> message(150'000);
  for (size_t i = 0; i < message.size(); ++i) message[i] = uint8_t(i * 7 + 3);
  const auto wire = sealer.seal_message(message);
  // Three records: 64 KiB, 64 KiB, the rest; each a header, the flag and the tag more.
  CHECK(wire.size() == message.size() + 3 * (kRecordHeaderSize + kRecordFlagSize + kRecordTagSize));
  CHECK(wire.size() == sealed_size(message.size()));
  CHECK(sealer.seal_message(std::vector<uint8_t>(10)).size() == sealed_size(10));
  std::vector<uint8_t> out;
  std::string reason;
  size_t at = 0;
  int records = 0, complete_count = 0;
  while (at < wire.size()) {
    RecordHeader header;
    REQUIRE(opener.check_header(std::span(wire).subspan(at, kRecordHeaderSize), &header, &reason) == RecordError::None);
    CHECK(header.ciphertext_length <= kMaxRecordCiphertext);
    bool complete = false;
    REQUIRE(opener.open(std::span(wire).subspan(at, kRecordHeaderSize),
                        std::span(wire).subspan(at + kRecordHeaderSize, header.ciphertext_length), &out, &reason,
                        &complete) == RecordError::None);
    ++records;
    complete_count += complete;
    CHECK(complete == (records == 3));
    at += kRecordHeaderSize + header.ciphertext_length;
  }
  CHECK(records == 3);
  CHECK(complete_count == 1);
  CHECK(out == message);

  // A message growing past the opener's limit is refused, fragment by fragment.
  RecordOpener small(pair.listener.keys().receive, 100'000);
  RecordSealer again(pair.connector.keys().send);
  const auto big = again.seal_message(message);
  size_t first_length = 0;
  std::memcpy(&first_length, big.data(), 4);
  bool complete = true;
  REQUIRE(small.open(std::span(big).first(kRecordHeaderSize), std::span(big).subspan(kRecordHeaderSize, first_length), &out,
                     &reason, &complete) == RecordError::None);
  CHECK_FALSE(complete);
  CHECK(out.empty());
  const size_t second_at = kRecordHeaderSize + first_length;
  CHECK(small.open(std::span(big).subspan(second_at, kRecordHeaderSize),
                   std::span(big).subspan(second_at + kRecordHeaderSize, first_length), &out, &reason) == RecordError::BadFragment);
  CHECK_THAT(reason, Catch::Contains("more than 100000 bytes"));
}

TEST_CASE("traffic keys are wiped when their sealer and opener go, session keys when a copy goes") {
  std::array<uint8_t, kTrafficKeySize> key{};
  randombytes_buf(key.data(), key.size());
  auto holds_key = [&](std::span<const std::byte> storage) {
    const auto* bytes = reinterpret_cast<const uint8_t*>(storage.data());
    return std::search(bytes, bytes + storage.size(), key.begin(), key.end()) != bytes + storage.size();
  };
  alignas(RecordSealer) std::byte sealer_storage[sizeof(RecordSealer)];
  auto* sealer = new (sealer_storage) RecordSealer(key);
  CHECK(holds_key(sealer_storage));
  sealer->~RecordSealer();
  CHECK_FALSE(holds_key(sealer_storage));
  // The session key too: every copy (options are copied around) wipes itself.
  alignas(SessionKey) std::byte key_storage[sizeof(SessionKey)];
  auto* session_key = new (key_storage) SessionKey();
  std::copy(key.begin(), key.end(), session_key->bytes.begin());
  CHECK(holds_key(key_storage));
  session_key->~SessionKey();
  CHECK_FALSE(holds_key(key_storage));
  alignas(RecordOpener) std::byte opener_storage[sizeof(RecordOpener)];
  auto* opener = new (opener_storage) RecordOpener(key, 1000);
  CHECK(holds_key(opener_storage));
  opener->~RecordOpener();
  CHECK_FALSE(holds_key(opener_storage));
}
