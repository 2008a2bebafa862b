#pragma once
// Keys, handshake and record protection with libsodium (no home-made primitives). No sockets
// here: session.cpp moves these bytes over Asio, and the tests drive them directly.
//
// Pre-shared session key K (32 bytes). The handshake is modelled on Noise's NNpsk0: ephemeral
// X25519 keys on both sides, mixed with K, so that the traffic keys need both K and one side's
// ephemeral secret, which is wiped once used (forward secrecy: whoever records the traffic and
// later learns K still cannot decrypt it). Built from libsodium's X25519 (crypto_scalarmult)
// and BLAKE2b (crypto_generichash); it is not wire-compatible with Noise.
//   1. each sends HELLO = "RTHS" | version u16 | role u8 | reserved u8 = 0 | 32-byte random
//      nonce | 32-byte ephemeral X25519 public key
//   2. both compute the transcript hash h = BLAKE2b-256("RemoteTouch/2 transcript" | connector's
//      hello | listener's hello) over every byte of both hellos, the X25519 shared secret dh of
//      their ephemeral secret and the peer's public key (refused if it is a low-order point), and
//      the handshake secret s = BLAKE2b-256 keyed with K over "RemoteTouch/2 secret" | h | dh.
//      The ephemeral secret and dh are wiped at once.
//   3. PROOF = BLAKE2b-256 keyed with s over "RemoteTouch/2 proof" | role. The connector sends
//      its proof first; the listener checks it (constant time) before it sends its own, so that
//      nothing the listener sends proves K to a peer that has not proved it first. A listener
//      that refuses the connector's proof sends random bytes in its place (they prove nothing)
//      and closes, so that both sides refuse a wrong key, each with a log line.
// Traffic keys, one per direction, are BLAKE2b-256 keyed with s over a direction label. Each
// RECORD then carries one message:
//   ciphertext length u32 | counter u64 | XChaCha20-Poly1305(message), the 12-byte header as
//   associated data, nonce = the counter. Counters start at 1 and go up by one: TCP loses
//   nothing, so a gap means a record was deleted on the way (record sizes tell the message
//   types apart, so touch events could be deleted selectively), a repeat or a step back that
//   one was replayed or reordered. Any of these is an authentication failure (OutOfSequence):
//   the session ends the connection and builds a new one.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace rt::net {

struct SessionKey {
  std::array<uint8_t, 32> bytes{};
};

// 64 hex digits (surrounding whitespace ignored). Throws std::invalid_argument saying what is wrong.
SessionKey session_key_from_hex(const std::string& hex);
// A key file holds the key as 64 hex digits (one line), readable by its owner only. Refused,
// naming the file: not a regular file, longer than a key's line, not a key, a weak key (every
// byte the same, see is_weak_session_key), or readable by the group or others. Throws
// std::invalid_argument.
SessionKey load_session_key_file(const std::filesystem::path& path);
// Writes a new random key to `path` (mode 0600, never over an existing file or through a
// symbolic link) and returns it. Throws std::runtime_error saying why it could not.
SessionKey write_new_session_key_file(const std::filesystem::path& path);
SessionKey random_session_key();
// Every byte the same (all zero, say): a placeholder, not a secret. Sessions refuse one.
bool is_weak_session_key(const SessionKey& key);
std::string to_hex(const SessionKey& key);

// Initialises libsodium once; throws if it cannot.
void ensure_sodium();

enum class Role : uint8_t { Connector = 1, Listener = 2 };
const char* role_name(Role role);

inline constexpr uint16_t kHandshakeVersion = 2;  // 1: proofs keyed with K alone, no ephemeral keys
inline constexpr size_t kHelloPrefixSize = 8;     // magic, version, role, reserved: read first
inline constexpr size_t kHelloSize = 72;
inline constexpr size_t kProofSize = 32;
inline constexpr size_t kTrafficKeySize = 32;
inline constexpr size_t kRecordHeaderSize = 12;
inline constexpr size_t kRecordTagSize = 16;

struct TrafficKeys {
  std::array<uint8_t, kTrafficKeySize> send{}, receive{};
};

class Handshake {
 public:
  Handshake(const SessionKey& key, Role role);
  // Tests only: a chosen nonce (the ephemeral key is still fresh).
  Handshake(const SessionKey& key, Role role, const std::array<uint8_t, 32>& nonce);
  ~Handshake();  // wipes the key copy, the ephemeral secret and the handshake secret
  Handshake(const Handshake&) = delete;
  Handshake& operator=(const Handshake&) = delete;

  std::array<uint8_t, kHelloSize> hello() const;
  // The first kHelloPrefixSize bytes of the peer's hello: magic, version (an older peer gets a
  // clear error before the rest of its shorter hello is awaited), role, reserved byte.
  // Before any handshake exists: a listener makes its ephemeral key only for a peer whose hello
  // starts right.
  static std::optional<std::string> check_hello_prefix(std::span<const uint8_t> prefix, Role own_role);
  // Whether a hello's first bytes carry RemoteTouch's magic (whatever version follows).
  static bool has_hello_magic(std::span<const uint8_t> prefix);
  // Checks the whole hello (the prefix again, a nonce and an ephemeral key not equal to ours,
  // an ephemeral key of full order) and derives the handshake secret; the ephemeral secret is
  // wiped whatever the outcome. Once only: a handshake that refused a hello is spent.
  std::optional<std::string> receive_hello(std::span<const uint8_t> hello);
  // The connector's: after receive_hello succeeded. The listener's: only after verify_proof
  // accepted the connector's (throws std::logic_error otherwise).
  std::array<uint8_t, kProofSize> proof() const;
  // What a listener sends instead of its proof to a connector it refused: random bytes.
  static std::array<uint8_t, kProofSize> decoy_proof();
  // Empty on success: the peer knows K and took part in this handshake. Afterwards keys() are valid.
  std::optional<std::string> verify_proof(std::span<const uint8_t> proof);
  TrafficKeys keys() const;
  // Wipes what is left of the secrets once the traffic keys are taken; complete() still holds.
  void wipe();
  bool complete() const { return verified_; }

  // h over both hellos, every byte (tests check that each one counts).
  static std::array<uint8_t, 32> transcript_hash(std::span<const uint8_t> connector_hello,
                                                 std::span<const uint8_t> listener_hello);

 private:
  std::array<uint8_t, kProofSize> proof_of(Role role) const;

  std::array<uint8_t, 32> key_{};
  Role role_;
  std::array<uint8_t, 32> own_nonce_{};
  std::array<uint8_t, 32> ephemeral_secret_{}, ephemeral_public_{};
  std::array<uint8_t, 32> secret_{};  // s: valid once have_peer_, until wipe()
  bool hello_seen_ = false, have_peer_ = false, verified_ = false, wiped_ = false;
};

// Seals outgoing records with increasing counters.
class RecordSealer {
 public:
  explicit RecordSealer(const std::array<uint8_t, kTrafficKeySize>& key) : key_(key) {}
  std::vector<uint8_t> seal(std::span<const uint8_t> plaintext);
  // The counter the next record gets (tests use it to forge replays).
  uint64_t next_counter() const { return counter_; }

 private:
  std::array<uint8_t, kTrafficKeySize> key_;
  uint64_t counter_ = 1;
};

// OutOfSequence: authentic, but its counter is not the one after the last (deleted, replayed or
// reordered on the way). Every error ends the connection.
enum class RecordError { None, Oversize, AuthFailed, OutOfSequence };
const char* record_error_name(RecordError error);

struct RecordHeader {
  uint32_t ciphertext_length = 0;
  uint64_t counter = 0;
};

class RecordOpener {
 public:
  RecordOpener(const std::array<uint8_t, kTrafficKeySize>& key, size_t max_plaintext)
      : key_(key), max_plaintext_(max_plaintext) {}
  // Oversize (or shorter than the tag): the byte stream cannot be trusted to be in step any more.
  RecordError check_header(std::span<const uint8_t> header, RecordHeader* out, std::string* reason) const;
  // AuthFailed: forged, corrupted, or out of step. OutOfSequence: authentic, but its counter is
  // not last_counter() + 1. Either way nothing is returned.
  RecordError open(std::span<const uint8_t> header, std::span<const uint8_t> ciphertext, std::vector<uint8_t>* plaintext,
                   std::string* reason);
  uint64_t last_counter() const { return last_; }

 private:
  std::array<uint8_t, kTrafficKeySize> key_;
  size_t max_plaintext_;
  uint64_t last_ = 0;
};

}  // namespace rt::net
