#pragma once
// Keys, handshake and record protection with libsodium (no home-made primitives). No sockets
// here: session.cpp moves these bytes over Asio, and the tests drive them directly.
//
// Pre-shared session key K (32 bytes). Handshake, both sides at once:
//   1. each sends HELLO = "RTHS" | version u16 | role u8 | 0 u8 | 32-byte random nonce
//   2. on the peer's hello, each sends PROOF = BLAKE2b-256 keyed with K over
//      "RemoteTouch/1 proof" | own role | connector nonce | listener nonce
//   3. each checks the peer's proof (constant time). A wrong proof: no session (both sides log
//      it, since both check), and nothing of the peer's is ever decoded.
// Traffic keys, one per direction, are BLAKE2b-256 keyed with K over a direction label and both
// nonces, so they are fresh for every connection. Each RECORD then carries one message:
//   ciphertext length u32 | counter u64 | XChaCha20-Poly1305(message), the 12-byte header as
//   associated data, nonce = the counter. A receiver accepts only counters above the last one it
//   accepted (a replayed or reordered record is refused; a gap counts as records missing).
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
// byte the same), or readable by the group or others. Throws std::invalid_argument.
SessionKey load_session_key_file(const std::filesystem::path& path);
// Writes a new random key to `path` (mode 0600, never over an existing file or through a
// symbolic link) and returns it. Throws std::runtime_error saying why it could not.
SessionKey write_new_session_key_file(const std::filesystem::path& path);
SessionKey random_session_key();
std::string to_hex(const SessionKey& key);

// Initialises libsodium once; throws if it cannot.
void ensure_sodium();

enum class Role : uint8_t { Connector = 1, Listener = 2 };
const char* role_name(Role role);

inline constexpr size_t kHelloSize = 40;
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
  ~Handshake();  // wipes the key copy
  Handshake(const Handshake&) = delete;
  Handshake& operator=(const Handshake&) = delete;

  std::array<uint8_t, kHelloSize> hello() const;
  // Checks the peer's hello (magic, version, the opposite role, a nonce not equal to ours).
  std::optional<std::string> receive_hello(std::span<const uint8_t> hello);
  // Only after receive_hello succeeded.
  std::array<uint8_t, kProofSize> proof() const;
  // Empty on success: the peer knows K. Afterwards keys() are valid.
  std::optional<std::string> verify_proof(std::span<const uint8_t> proof);
  TrafficKeys keys() const;
  bool complete() const { return verified_; }

 private:
  std::array<uint8_t, kProofSize> proof_of(Role role) const;

  std::array<uint8_t, 32> key_{};
  Role role_;
  std::array<uint8_t, 32> own_nonce_{}, peer_nonce_{};
  bool have_peer_ = false, verified_ = false;
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

enum class RecordError { None, Oversize, AuthFailed, Replay };
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
  // AuthFailed: forged, corrupted, or out of step. Replay: authentic, but its counter is not new.
  RecordError open(std::span<const uint8_t> header, std::span<const uint8_t> ciphertext, std::vector<uint8_t>* plaintext,
                   std::string* reason);
  uint64_t records_missing() const { return missing_; }
  uint64_t last_counter() const { return last_; }

 private:
  std::array<uint8_t, kTrafficKeySize> key_;
  size_t max_plaintext_;
  uint64_t last_ = 0;
  uint64_t missing_ = 0;
};

}  // namespace rt::net
