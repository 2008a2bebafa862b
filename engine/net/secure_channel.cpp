#include "net/secure_channel.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace rt::net {
namespace {

constexpr uint8_t kHelloMagic[4] = {'R', 'T', 'H', 'S'};
// Hello: magic 0..3 | version 4..5 | role 6 | reserved 7 | nonce 8..39 | ephemeral public key 40..71 |
// timestamp 72..79 | MAC 80..111.
constexpr size_t kNonceAt = 8, kEphemeralAt = 40, kTimestampAt = 72;
static_assert(kTimestampAt + 8 == kHelloMacAt);
static_assert(kHelloMacSize == crypto_auth_BYTES);
// crypto_kdf's context: eight characters naming what the subkey is for.
constexpr char kHelloKdfContext[crypto_kdf_CONTEXTBYTES + 1] = "RTHello1";
constexpr uint64_t kHelloKdfSubkeyId = 1;

// BLAKE2b-256 over the concatenation of `parts`, keyed with `key` (unkeyed when it is null).
std::array<uint8_t, 32> hash_of(const std::array<uint8_t, 32>* key, std::initializer_list<std::span<const uint8_t>> parts) {
  crypto_generichash_state state;
  crypto_generichash_init(&state, key ? key->data() : nullptr, key ? key->size() : 0, 32);
  for (auto part : parts) crypto_generichash_update(&state, part.data(), part.size());
  std::array<uint8_t, 32> out{};
  crypto_generichash_final(&state, out.data(), out.size());
  sodium_memzero(&state, sizeof state);
  return out;
}
std::array<uint8_t, 32> keyed_hash(const std::array<uint8_t, 32>& key, std::initializer_list<std::span<const uint8_t>> parts) {
  return hash_of(&key, parts);
}

std::span<const uint8_t> text(const char* label) { return {reinterpret_cast<const uint8_t*>(label), std::strlen(label)}; }

std::array<uint8_t, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES> nonce_of(uint64_t counter) {
  std::array<uint8_t, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES> nonce{};
  std::memcpy(nonce.data(), &counter, sizeof counter);
  return nonce;
}

}  // namespace

SessionKey::~SessionKey() { sodium_memzero(bytes.data(), bytes.size()); }

void ensure_sodium() {
  static const int result = sodium_init();  // thread-safe, idempotent
  if (result < 0) throw std::runtime_error("libsodium failed to initialise");
}

SessionKey session_key_from_hex(std::string_view hex) {
  while (!hex.empty() && std::isspace(uint8_t(hex.front()))) hex.remove_prefix(1);
  while (!hex.empty() && std::isspace(uint8_t(hex.back()))) hex.remove_suffix(1);
  if (hex.size() != 64)
    throw std::invalid_argument("session key: expected 64 hex digits (32 bytes), got " + std::to_string(hex.size()) +
                                " characters");
  SessionKey key;
  // A view, no copy: nothing of the key's text is left behind; the errors name a position only.
  for (size_t i = 0; i < 64; ++i) {
    const char c = hex[i];
    int digit = -1;
    if (c >= '0' && c <= '9') digit = c - '0';
    if (c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') digit = c - 'A' + 10;
    if (digit < 0) {
      sodium_memzero(key.bytes.data(), key.bytes.size());
      throw std::invalid_argument("session key: character " + std::to_string(i + 1) + " of 64 is not a hex digit");
    }
    key.bytes[i / 2] = uint8_t(key.bytes[i / 2] | digit << (i % 2 ? 0 : 4));
  }
  return key;
}

namespace {

// 64 hex digits and a line end, with room for a CR and surrounding spaces.
constexpr size_t kMaxKeyFileBytes = 80;

// Closes the descriptor and wipes what was read, whichever way the function leaves.
struct KeyFileBuffer {
  int fd = -1;
  std::array<char, kMaxKeyFileBytes + 1> bytes{};
  ~KeyFileBuffer() {
    sodium_memzero(bytes.data(), bytes.size());
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

SessionKey load_session_key_file(const std::filesystem::path& path) {
  const std::string name = "session key file " + path.string();
  KeyFileBuffer buffer;
  // Non-blocking: a FIFO named as the key must not hang the site before it is refused.
  buffer.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (buffer.fd < 0) throw std::invalid_argument(name + " cannot be opened: " + std::strerror(errno));
  // Who may have seen or changed the key, before anything of it is read: a key others could read
  // or write is no secret between two sites.
  struct stat info {};
  if (::fstat(buffer.fd, &info) != 0 || !S_ISREG(info.st_mode))
    throw std::invalid_argument(name + " is not a regular file");
  if (info.st_uid != ::geteuid())
    throw std::invalid_argument(name + " belongs to user " + std::to_string(info.st_uid) + ", not to us (user " +
                                std::to_string(::geteuid()) + "): make our own with remotetouch keygen FILE");
  if (info.st_mode & (S_IRWXG | S_IRWXO)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", unsigned(info.st_mode & 07777));
    throw std::invalid_argument(name + " is open to the group or others (mode " + mode + "): chmod 600 " + path.string());
  }
  if (info.st_size > off_t(kMaxKeyFileBytes))
    throw std::invalid_argument(name + " is " + std::to_string(info.st_size) + " bytes, longer than a key's line (64 hex digits)");
  size_t size = 0;
  while (size < buffer.bytes.size()) {
    const ssize_t n = ::read(buffer.fd, buffer.bytes.data() + size, buffer.bytes.size() - size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::invalid_argument(name + " cannot be read: " + std::strerror(errno));
    if (n == 0) break;
    size += size_t(n);
  }
  if (size > kMaxKeyFileBytes) throw std::invalid_argument(name + " is longer than a key's line (64 hex digits)");
  SessionKey key;
  try {
    key = session_key_from_hex(std::string_view(buffer.bytes.data(), size));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path.string() + ": " + e.what());
  }
  if (is_weak_session_key(key)) {
    sodium_memzero(key.bytes.data(), key.bytes.size());
    throw std::invalid_argument(name + " holds a weak key (too regular to be a secret: a placeholder or a hand-typed "
                                       "key): make one with remotetouch keygen FILE");
  }
  return key;
}

SessionKey write_new_session_key_file(const std::filesystem::path& path) {
  const SessionKey key = random_session_key();
  // Made where it stays: no hex copy of the key left behind in a freed buffer.
  std::string line;
  line.reserve(66);
  {
    std::string hex = to_hex(key);
    line.append(hex);
    sodium_memzero(hex.data(), hex.size());
  }
  line += '\n';
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) {
    sodium_memzero(line.data(), line.size());
    throw std::runtime_error("cannot create the key file " + path.string() + ": " + std::strerror(errno) +
                             (errno == EEXIST ? " (a key file is never overwritten: remove it first)" : ""));
  }
  size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::write(fd, line.data() + written, line.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    written += size_t(n);
  }
  const bool ok = written == line.size() && ::fsync(fd) == 0;
  ::close(fd);
  sodium_memzero(line.data(), line.size());
  if (!ok) throw std::runtime_error("cannot write the key file " + path.string() + ": " + std::strerror(errno));
  return key;
}

SessionKey random_session_key() {
  ensure_sodium();
  SessionKey key;
  randombytes_buf(key.bytes.data(), key.bytes.size());
  return key;
}

bool is_weak_session_key(const SessionKey& key) {
  std::array<bool, 256> value_seen{}, step_seen{};
  int values = 0, steps = 0;
  for (size_t i = 0; i < key.bytes.size(); ++i) {
    if (!std::exchange(value_seen[key.bytes[i]], true)) ++values;
    if (i > 0 && !std::exchange(step_seen[uint8_t(key.bytes[i] - key.bytes[i - 1])], true)) ++steps;
  }
  constexpr int kFewest = 16;
  return values < kFewest || steps < kFewest;
}

std::string to_hex(const SessionKey& key) {
  char out[65];
  sodium_bin2hex(out, sizeof out, key.bytes.data(), key.bytes.size());
  std::string hex(out, 64);
  sodium_memzero(out, sizeof out);
  return hex;
}

HelloAuthenticator::HelloAuthenticator(const SessionKey& key) {
  ensure_sodium();
  static_assert(sizeof key_ == crypto_auth_KEYBYTES);
  crypto_kdf_derive_from_key(key_.data(), key_.size(), kHelloKdfSubkeyId, kHelloKdfContext, key.bytes.data());
}

HelloAuthenticator::~HelloAuthenticator() { sodium_memzero(key_.data(), key_.size()); }

void HelloAuthenticator::sign(std::span<uint8_t> hello) const {
  if (hello.size() != kHelloSize) throw std::logic_error("hello MAC: a hello of the wrong size");
  crypto_auth(hello.data() + kHelloMacAt, hello.data(), kHelloMacAt, key_.data());
}

bool HelloAuthenticator::verify(std::span<const uint8_t> hello) const {
  return hello.size() == kHelloSize && crypto_auth_verify(hello.data() + kHelloMacAt, hello.data(), kHelloMacAt, key_.data()) == 0;
}

uint64_t hello_timestamp(std::span<const uint8_t> hello) {
  uint64_t timestamp = 0;
  if (hello.size() >= kTimestampAt + 8) std::memcpy(&timestamp, hello.data() + kTimestampAt, 8);
  return timestamp;
}

uint64_t next_hello_timestamp() {
  static std::atomic<uint64_t> last{0};
  const uint64_t now = uint64_t(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count());
  uint64_t previous = last.load();
  uint64_t next = 0;
  do next = std::max(now, previous + 1);
  while (!last.compare_exchange_weak(previous, next));
  return next;
}

HelloVerdict HelloGate::check(std::span<const uint8_t> hello) {
  if (!authenticator_.verify(hello)) return HelloVerdict::NotAuthentic;
  const uint64_t timestamp = hello_timestamp(hello);
  if (timestamp <= last_accepted_) return HelloVerdict::Replayed;
  last_accepted_ = timestamp;
  return HelloVerdict::Accepted;
}

const char* role_name(Role role) { return role == Role::Connector ? "connector" : "listener"; }

Handshake::Handshake(const SessionKey& key, Role role)
    : key_(key.bytes), role_(role), authenticator_(key), timestamp_(next_hello_timestamp()) {
  if (is_weak_session_key(key)) throw std::invalid_argument("handshake: a weak session key (too regular to be a secret)");
  randombytes_buf(own_nonce_.data(), own_nonce_.size());
  randombytes_buf(ephemeral_secret_.data(), ephemeral_secret_.size());
  crypto_scalarmult_base(ephemeral_public_.data(), ephemeral_secret_.data());
}

Handshake::Handshake(const SessionKey& key, Role role, const std::array<uint8_t, 32>& nonce) : Handshake(key, role) {
  own_nonce_ = nonce;
}

Handshake::Handshake(const SessionKey& key, Role role, uint64_t timestamp) : Handshake(key, role) { timestamp_ = timestamp; }

Handshake::~Handshake() {
  sodium_memzero(ephemeral_secret_.data(), ephemeral_secret_.size());
  wipe();
}

void Handshake::wipe() {
  sodium_memzero(key_.data(), key_.size());
  sodium_memzero(secret_.data(), secret_.size());
  wiped_ = true;
}

std::array<uint8_t, kHelloPrefixSize> Handshake::hello_prefix(Role role) {
  std::array<uint8_t, kHelloPrefixSize> out{};
  std::memcpy(out.data(), kHelloMagic, 4);
  std::memcpy(out.data() + 4, &kHandshakeVersion, 2);
  out[6] = uint8_t(role);
  out[7] = 0;
  return out;
}

std::array<uint8_t, kHelloSize> Handshake::hello() const {
  std::array<uint8_t, kHelloSize> out{};
  const auto prefix = hello_prefix(role_);
  std::memcpy(out.data(), prefix.data(), prefix.size());
  std::memcpy(out.data() + kNonceAt, own_nonce_.data(), 32);
  std::memcpy(out.data() + kEphemeralAt, ephemeral_public_.data(), 32);
  std::memcpy(out.data() + kTimestampAt, &timestamp_, 8);
  authenticator_.sign(out);
  return out;
}

bool Handshake::has_hello_magic(std::span<const uint8_t> prefix) {
  return prefix.size() >= 4 && std::memcmp(prefix.data(), kHelloMagic, 4) == 0;
}

std::optional<std::string> Handshake::check_hello_prefix(std::span<const uint8_t> prefix, Role own_role) {
  if (prefix.size() < kHelloPrefixSize) return std::string("handshake: hello too short");
  if (std::memcmp(prefix.data(), kHelloMagic, 4) != 0) return std::string("handshake: the peer does not speak RemoteTouch (bad hello magic)");
  uint16_t version = 0;
  std::memcpy(&version, prefix.data() + 4, 2);
  if (version != kHandshakeVersion)
    return "handshake: the peer speaks protocol version " + std::to_string(version) + ", this build version " +
           std::to_string(kHandshakeVersion) + " (run the same release at both sites)";
  const Role expected = own_role == Role::Connector ? Role::Listener : Role::Connector;
  if (prefix[6] != uint8_t(expected)) return std::string("handshake: peer claims the wrong role (a reflected hello?)");
  if (prefix[7] != 0)
    return "handshake: the hello's reserved byte is " + std::to_string(prefix[7]) + ", not 0 (tampered with, or a newer peer)";
  return std::nullopt;
}

std::array<uint8_t, 32> Handshake::transcript_hash(std::span<const uint8_t> connector_hello,
                                                    std::span<const uint8_t> listener_hello) {
  return hash_of(nullptr, {text("RemoteTouch/2 transcript"), connector_hello, listener_hello});
}

std::optional<std::string> Handshake::receive_hello(std::span<const uint8_t> hello) {
  if (hello_seen_ || wiped_) return std::string("handshake: a second hello");
  hello_seen_ = true;
  // The ephemeral secret serves this one exchange: wiped on every way out.
  struct Wipe {
    std::array<uint8_t, 32>& bytes;
    ~Wipe() { sodium_memzero(bytes.data(), bytes.size()); }
  } wipe_secret{ephemeral_secret_};
  if (hello.size() != kHelloSize)
    return "handshake: hello of " + std::to_string(hello.size()) + " bytes, expected " + std::to_string(kHelloSize);
  if (auto error = check_hello_prefix(hello, role_)) return error;
  if (!authenticator_.verify(hello))
    return std::string("handshake: the peer's hello is not authenticated with our session key (wrong key on one side?)");
  if (sodium_memcmp(hello.data() + kNonceAt, own_nonce_.data(), 32) == 0 ||
      sodium_memcmp(hello.data() + kEphemeralAt, ephemeral_public_.data(), 32) == 0)
    return std::string("handshake: peer echoed our nonce or key (a reflected hello)");
  std::array<uint8_t, 32> dh{};
  Wipe wipe_dh{dh};
  // Fails for a low-order public key (the shared secret would be all zero, known to anyone).
  if (crypto_scalarmult(dh.data(), ephemeral_secret_.data(), hello.data() + kEphemeralAt) != 0)
    return std::string("handshake: the peer's ephemeral key is a weak (low-order) point");
  const auto own = this->hello();
  const auto h = role_ == Role::Connector ? transcript_hash(own, hello) : transcript_hash(hello, own);
  secret_ = keyed_hash(key_, {text("RemoteTouch/2 secret"), h, dh});
  have_peer_ = true;
  return std::nullopt;
}

std::array<uint8_t, kProofSize> Handshake::proof_of(Role role) const {
  const uint8_t role_byte = uint8_t(role);
  return keyed_hash(secret_, {text("RemoteTouch/2 proof"), {&role_byte, 1}});
}

std::array<uint8_t, kProofSize> Handshake::proof() const {
  if (!have_peer_ || wiped_) throw std::logic_error("handshake: proof before the peer's hello");
  if (role_ == Role::Listener && !verified_)
    throw std::logic_error("handshake: the listener proves the key only after the connector has");
  return proof_of(role_);
}

std::array<uint8_t, kProofSize> Handshake::decoy_proof() {
  ensure_sodium();
  std::array<uint8_t, kProofSize> out{};
  randombytes_buf(out.data(), out.size());
  return out;
}

std::optional<std::string> Handshake::verify_proof(std::span<const uint8_t> proof) {
  if (!have_peer_ || wiped_) return std::string("handshake: proof before hello");
  if (verified_) return std::string("handshake: a second proof");
  if (proof.size() != kProofSize) return std::string("handshake: proof of the wrong size");
  const auto expected = proof_of(role_ == Role::Connector ? Role::Listener : Role::Connector);
  if (sodium_memcmp(expected.data(), proof.data(), kProofSize) != 0)
    return std::string("handshake refused: the peer did not prove knowledge of the session key (wrong key?)");
  verified_ = true;
  return std::nullopt;
}

TrafficKeys Handshake::keys() const {
  if (!verified_) throw std::logic_error("handshake: keys before the peer's proof was verified");
  if (wiped_) throw std::logic_error("handshake: keys after the secrets were wiped");
  const auto to_listener = keyed_hash(secret_, {text("RemoteTouch/2 key connector->listener")});
  const auto to_connector = keyed_hash(secret_, {text("RemoteTouch/2 key listener->connector")});
  TrafficKeys keys;
  keys.send = role_ == Role::Connector ? to_listener : to_connector;
  keys.receive = role_ == Role::Connector ? to_connector : to_listener;
  return keys;
}

RecordSealer::~RecordSealer() { sodium_memzero(key_.data(), key_.size()); }

namespace {

void seal_into(std::vector<uint8_t>& out, std::span<const uint8_t> fragment, bool final, uint64_t counter,
               const std::array<uint8_t, kTrafficKeySize>& key) {
  if (fragment.size() > kMaxRecordPayload) throw std::logic_error("record: a fragment over kMaxRecordPayload");
  const size_t at = out.size();
  out.resize(at + kRecordHeaderSize + kRecordFlagSize + fragment.size() + kRecordTagSize);
  uint8_t* record = out.data() + at;
  const uint32_t length = uint32_t(kRecordFlagSize + fragment.size() + kRecordTagSize);
  std::memcpy(record, &length, 4);
  std::memcpy(record + 4, &counter, 8);
  // The flag and the fragment side by side in the output, then encrypted in place.
  uint8_t* plaintext = record + kRecordHeaderSize;
  plaintext[0] = final ? 1 : 0;
  if (!fragment.empty()) std::memcpy(plaintext + kRecordFlagSize, fragment.data(), fragment.size());
  const auto nonce = nonce_of(counter);
  unsigned long long written = 0;
  crypto_aead_xchacha20poly1305_ietf_encrypt(plaintext, &written, plaintext, kRecordFlagSize + fragment.size(), record,
                                             kRecordHeaderSize, nullptr, nonce.data(), key.data());
}

}  // namespace

std::vector<uint8_t> RecordSealer::seal(std::span<const uint8_t> fragment, bool final) {
  std::vector<uint8_t> out;
  seal_into(out, fragment, final, counter_++, key_);
  return out;
}

std::vector<uint8_t> RecordSealer::seal_message(std::span<const uint8_t> message) {
  const size_t records = std::max<size_t>(1, (message.size() + kMaxRecordPayload - 1) / kMaxRecordPayload);
  std::vector<uint8_t> out;
  out.reserve(message.size() + records * (kRecordHeaderSize + kRecordFlagSize + kRecordTagSize));
  for (size_t i = 0; i < records; ++i) {
    const size_t at = i * kMaxRecordPayload;
    seal_into(out, message.subspan(at, std::min(kMaxRecordPayload, message.size() - at)), i + 1 == records, counter_++,
              key_);
  }
  return out;
}

const char* record_error_name(RecordError error) {
  switch (error) {
    case RecordError::None: return "none";
    case RecordError::Oversize: return "record_oversize";
    case RecordError::AuthFailed: return "auth_failed";
    case RecordError::OutOfSequence: return "out_of_sequence";
    case RecordError::BadFragment: return "bad_fragment";
  }
  return "unknown";
}

RecordOpener::RecordOpener(const std::array<uint8_t, kTrafficKeySize>& key, size_t max_message)
    : key_(key), max_message_(max_message) {
  fragment_.reserve(kMaxRecordCiphertext);
}

RecordOpener::~RecordOpener() {
  sodium_memzero(key_.data(), key_.size());
  sodium_memzero(fragment_.data(), fragment_.size());
  sodium_memzero(partial_.data(), partial_.size());
}

RecordError RecordOpener::check_header(std::span<const uint8_t> header, RecordHeader* out, std::string* reason) const {
  std::memcpy(&out->ciphertext_length, header.data(), 4);
  std::memcpy(&out->counter, header.data() + 4, 8);
  constexpr size_t kShortest = kRecordFlagSize + kRecordTagSize;
  if (out->ciphertext_length < kShortest || out->ciphertext_length > kMaxRecordCiphertext) {
    *reason = "record length " + std::to_string(out->ciphertext_length) + " outside " + std::to_string(kShortest) + ".." +
              std::to_string(kMaxRecordCiphertext) + ": the stream is out of step";
    return RecordError::Oversize;
  }
  return RecordError::None;
}

RecordError RecordOpener::open(std::span<const uint8_t> header, std::span<const uint8_t> ciphertext,
                               std::vector<uint8_t>* message, std::string* reason, bool* complete) {
  message->clear();
  if (complete) *complete = false;
  RecordHeader h;
  if (auto e = check_header(header, &h, reason); e != RecordError::None) return e;
  if (ciphertext.size() != h.ciphertext_length) {
    *reason = "record body of " + std::to_string(ciphertext.size()) + " bytes, header says " + std::to_string(h.ciphertext_length);
    return RecordError::AuthFailed;
  }
  fragment_.resize(ciphertext.size() - kRecordTagSize);  // within the capacity reserved
  const auto nonce = nonce_of(h.counter);
  unsigned long long written = 0;
  if (crypto_aead_xchacha20poly1305_ietf_decrypt(fragment_.data(), &written, nullptr, ciphertext.data(), ciphertext.size(),
                                                 header.data(), kRecordHeaderSize, nonce.data(), key_.data()) != 0) {
    *reason = "record " + std::to_string(h.counter) + " failed authentication (tampered, forged or out of step)";
    return RecordError::AuthFailed;
  }
  if (h.counter != last_ + 1) {
    *reason = "record " + std::to_string(h.counter) + " out of sequence after " + std::to_string(last_) + " (" +
              (h.counter > last_ ? std::to_string(h.counter - last_ - 1) + " deleted on the way" : "replayed or reordered") + ")";
    return RecordError::OutOfSequence;
  }
  last_ = h.counter;
  const uint8_t flag = fragment_[0];
  const size_t bytes = fragment_.size() - kRecordFlagSize;
  if (flag > 1) {
    *reason = "record " + std::to_string(h.counter) + " has fragment flag " + std::to_string(flag) + ", not 0 or 1";
    return RecordError::BadFragment;
  }
  if (partial_.size() + bytes > max_message_) {
    *reason = "a message of more than " + std::to_string(max_message_) + " bytes (record " + std::to_string(h.counter) + ")";
    return RecordError::BadFragment;
  }
  partial_.insert(partial_.end(), fragment_.begin() + kRecordFlagSize, fragment_.end());
  if (flag == 0) return RecordError::None;
  if (complete) *complete = true;
  message->swap(partial_);
  partial_.clear();
  return RecordError::None;
}

}  // namespace rt::net
