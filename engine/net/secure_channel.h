#pragma once
// Keys, handshake and record protection with libsodium (no home-made primitives). No sockets
// here: session.cpp moves these bytes over Asio, and the tests drive them directly.
//
// Pre-shared session key K (32 bytes). The handshake is modelled on Noise's NNpsk0: ephemeral
// X25519 keys on both sides, mixed with K, so that the traffic keys need both K and one side's
// ephemeral secret, which is wiped once used (forward secrecy: whoever records the traffic and
// later learns K still cannot decrypt it). Built from libsodium's X25519 (crypto_scalarmult),
// BLAKE2b (crypto_generichash), HMAC-SHA-512-256 (crypto_auth) and crypto_kdf; it is not
// wire-compatible with Noise.
//   1. each sends HELLO = "RTHS" | version u16 | role u8 | reserved u8 = 0 | 32-byte random
//      nonce | 32-byte ephemeral X25519 public key | timestamp u64 | MAC[32], the MAC
//      crypto_auth over every byte before it, keyed with a key derived from K (crypto_kdf), as
//      Noise's psk0 payload tag or WireGuard's mac1. The listener checks the connector's MAC, and
//      that its timestamp is later than the last one it accepted (a replayed hello is refused),
//      before it makes any handshake state, key pair or reply: a stranger without K costs it a
//      read and a MAC. The timestamp is the connector's wall clock in microseconds, kept rising
//      within a run: a connector whose clock was set back is refused until it passes the last
//      hello the listener accepted (or the listener restarts), as WireGuard's initiations are.
//   2. both compute the transcript hash h = BLAKE2b-256("RemoteTouch/2 transcript" | connector's
//      hello | listener's hello) over every byte of both hellos, the X25519 shared secret dh of
//      their ephemeral secret and the peer's public key (refused if it is a low-order point), and
//      the handshake secret s = BLAKE2b-256 keyed with K over "RemoteTouch/2 secret" | h | dh.
//      The ephemeral secret and dh are wiped at once.
//   3. PROOF = BLAKE2b-256 keyed with s over "RemoteTouch/2 proof" | role. The connector sends
//      its proof first; the listener checks it (constant time) before it sends its own. The
//      listener's hello (its MAC proves K) goes only to a connector whose hello's MAC proved K
//      first, so that a stranger never gets anything from which to guess K offline. A listener
//      that refuses the connector's proof sends random bytes in its place (they prove nothing)
//      and closes, so that both sides refuse a wrong key, each with a log line.
// Traffic keys, one per direction, are BLAKE2b-256 keyed with s over a direction label, and wiped
// when the sealer or opener holding them goes. A message travels in RECORDS of at most
// kMaxRecordPayload of its bytes each, so that a slow link still brings a whole record, the only
// thing that counts as life, within the liveness timeout, and a length no one has authenticated
// yet never sizes more than one record's buffer:
//   ciphertext length u32 | counter u64 | XChaCha20-Poly1305(final u8 | fragment), the 12-byte
//   header as associated data, nonce = the counter; final is 1 on the message's last record, 0
//   on the others. Counters start at 1 and go up by one: TCP loses
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
#include <string_view>
#include <vector>

namespace rt::net {

// Every copy wipes itself when it goes (options are copied around; K must not linger in freed memory).
struct SessionKey {
  std::array<uint8_t, 32> bytes{};
  SessionKey() = default;
  SessionKey(const SessionKey&) = default;
  SessionKey& operator=(const SessionKey&) = default;
  ~SessionKey();
};

// 64 hex digits (surrounding whitespace ignored). Throws std::invalid_argument saying what is
// wrong, never quoting the text (it may be most of a key).
SessionKey session_key_from_hex(std::string_view hex);
// A key file holds the key as 64 hex digits (one line), owned by the user running us and readable
// by them only: both are checked before anything is read. Refused, naming the file: not a
// regular file, owned by someone else, readable by the group or others, longer than a key's
// line, not a key, a weak key (see is_weak_session_key). What was read is wiped. Throws
// std::invalid_argument.
SessionKey load_session_key_file(const std::filesystem::path& path);
// Writes a new random key to `path` (mode 0600, never over an existing file or through a
// symbolic link) and returns it. Throws std::runtime_error saying why it could not.
SessionKey write_new_session_key_file(const std::filesystem::path& path);
SessionKey random_session_key();
// Too regular to be a secret, as a placeholder or a hand-typed key is: fewer than 16 different
// byte values (a random key has about 30), or fewer than 16 different steps from one byte to the
// next (a counting sequence). A random key is refused with a probability far below 2^-64.
// Sessions and handshakes refuse one.
bool is_weak_session_key(const SessionKey& key);
// The caller wipes the copy (sodium_memzero) once done with it.
std::string to_hex(const SessionKey& key);

// Initialises libsodium once; throws if it cannot.
void ensure_sodium();

enum class Role : uint8_t { Connector = 1, Listener = 2 };
const char* role_name(Role role);

// The link's protocol version. 1: proofs keyed with K alone, no ephemeral keys; 2: hellos
// without a MAC, one record per message whatever its size.
inline constexpr uint16_t kHandshakeVersion = 3;
inline constexpr size_t kHelloPrefixSize = 8;     // magic, version, role, reserved: read first
inline constexpr size_t kHelloMacAt = 80;         // after the nonce, the ephemeral key and the timestamp
inline constexpr size_t kHelloMacSize = 32;
inline constexpr size_t kHelloSize = kHelloMacAt + kHelloMacSize;
inline constexpr size_t kProofSize = 32;
inline constexpr size_t kTrafficKeySize = 32;
inline constexpr size_t kRecordHeaderSize = 12;
inline constexpr size_t kRecordTagSize = 16;
inline constexpr size_t kRecordFlagSize = 1;  // final or not
inline constexpr size_t kMaxRecordPayload = 64 * 1024;  // a message's bytes in one record
// The most a receiver allocates for a record before it has authenticated it.
inline constexpr size_t kMaxRecordCiphertext = kRecordFlagSize + kMaxRecordPayload + kRecordTagSize;

// What a message of `message_bytes` costs on the wire: its records' headers, flags and tags included.
constexpr size_t sealed_size(size_t message_bytes) {
  const size_t records = message_bytes == 0 ? 1 : (message_bytes + kMaxRecordPayload - 1) / kMaxRecordPayload;
  return message_bytes + records * (kRecordHeaderSize + kRecordFlagSize + kRecordTagSize);
}

// The hello's MAC, keyed with a key derived from K: the listener's first check of a connector.
class HelloAuthenticator {
 public:
  explicit HelloAuthenticator(const SessionKey& key);
  ~HelloAuthenticator();  // wipes the derived key
  HelloAuthenticator(const HelloAuthenticator&) = delete;
  HelloAuthenticator& operator=(const HelloAuthenticator&) = delete;
  // Writes the MAC over the hello's first kHelloMacAt bytes into its last kHelloMacSize.
  void sign(std::span<uint8_t> hello) const;
  // Constant time. A hello of the wrong size is not authentic.
  bool verify(std::span<const uint8_t> hello) const;

 private:
  std::array<uint8_t, 32> key_{};
};

uint64_t hello_timestamp(std::span<const uint8_t> hello);  // the hello's full size
// Microseconds of the wall clock, never the same twice in a process and never going back in it.
uint64_t next_hello_timestamp();

// What a listener checks of a connector's hello before it spends anything on it: the MAC, then
// the replay window (the timestamp must be later than that of the last hello accepted). Nothing
// is allocated.
enum class HelloVerdict { Accepted, NotAuthentic, Replayed };
class HelloGate {
 public:
  explicit HelloGate(const SessionKey& key) : authenticator_(key) {}
  // The whole hello (kHelloSize bytes); its prefix has been checked already.
  HelloVerdict check(std::span<const uint8_t> hello);
  uint64_t last_accepted() const { return last_accepted_; }

 private:
  HelloAuthenticator authenticator_;
  uint64_t last_accepted_ = 0;
};

struct TrafficKeys {
  std::array<uint8_t, kTrafficKeySize> send{}, receive{};
};

class Handshake {
 public:
  Handshake(const SessionKey& key, Role role);
  // Tests only: a chosen nonce (the ephemeral key is still fresh).
  Handshake(const SessionKey& key, Role role, const std::array<uint8_t, 32>& nonce);
  // Tests only: a chosen timestamp, to replay or to send an old hello.
  Handshake(const SessionKey& key, Role role, uint64_t timestamp);
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
  // Our hello's first kHelloPrefixSize bytes: all a listener tells a peer of another version, from
  // which it learns ours, without the listener making a key pair or proving anything.
  static std::array<uint8_t, kHelloPrefixSize> hello_prefix(Role role);
  // Checks the whole hello (the prefix again, its MAC, a nonce and an ephemeral key not equal to
  // ours, an ephemeral key of full order) and derives the handshake secret; the ephemeral secret
  // is wiped whatever the outcome. Once only: a handshake that refused a hello is spent. The
  // replay window is the listener's session's (HelloGate), which sees every connection.
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
  HelloAuthenticator authenticator_;
  uint64_t timestamp_ = 0;
  std::array<uint8_t, 32> own_nonce_{};
  std::array<uint8_t, 32> ephemeral_secret_{}, ephemeral_public_{};
  std::array<uint8_t, 32> secret_{};  // s: valid once have_peer_, until wipe()
  bool hello_seen_ = false, have_peer_ = false, verified_ = false, wiped_ = false;
};

// Seals outgoing records with increasing counters.
class RecordSealer {
 public:
  explicit RecordSealer(const std::array<uint8_t, kTrafficKeySize>& key) : key_(key) {}
  ~RecordSealer();  // wipes the traffic key
  RecordSealer(const RecordSealer&) = delete;
  RecordSealer& operator=(const RecordSealer&) = delete;
  // One message in as many records as it takes (kMaxRecordPayload of it each), one after another.
  std::vector<uint8_t> seal_message(std::span<const uint8_t> message);
  // One record (tests forge with it): `fragment` at most kMaxRecordPayload bytes.
  std::vector<uint8_t> seal(std::span<const uint8_t> fragment, bool final = true);
  // The counter the next record gets (tests use it to forge replays).
  uint64_t next_counter() const { return counter_; }

 private:
  std::array<uint8_t, kTrafficKeySize> key_;
  uint64_t counter_ = 1;
};

// OutOfSequence: authentic, but its counter is not the one after the last (deleted, replayed or
// reordered on the way). BadFragment: authentic, but its flag is neither 0 nor 1, or its message
// grows past the limit (a peer holding the key, but buggy). Every error ends the connection.
enum class RecordError { None, Oversize, AuthFailed, OutOfSequence, BadFragment };
const char* record_error_name(RecordError error);

struct RecordHeader {
  uint32_t ciphertext_length = 0;
  uint64_t counter = 0;
};

// Opens records and puts their fragments back together into messages of at most `max_message`
// bytes; what it holds grows only by fragments that authenticated.
class RecordOpener {
 public:
  RecordOpener(const std::array<uint8_t, kTrafficKeySize>& key, size_t max_message);
  ~RecordOpener();  // wipes the traffic key and what it holds of a message
  RecordOpener(const RecordOpener&) = delete;
  RecordOpener& operator=(const RecordOpener&) = delete;
  // Oversize (longer than one record may be, or shorter than the flag and the tag): the byte
  // stream cannot be trusted to be in step any more.
  RecordError check_header(std::span<const uint8_t> header, RecordHeader* out, std::string* reason) const;
  // AuthFailed: forged, corrupted, or out of step. OutOfSequence: authentic, but its counter is
  // not last_counter() + 1. On None, *complete says whether this record ended a message, which is
  // then in *message (cleared otherwise); on an error nothing is returned.
  RecordError open(std::span<const uint8_t> header, std::span<const uint8_t> ciphertext, std::vector<uint8_t>* message,
                   std::string* reason, bool* complete = nullptr);
  uint64_t last_counter() const { return last_; }

 private:
  std::array<uint8_t, kTrafficKeySize> key_;
  size_t max_message_;
  uint64_t last_ = 0;
  std::vector<uint8_t> fragment_;  // one record's plaintext
  std::vector<uint8_t> partial_;   // the message so far
};

}  // namespace rt::net
