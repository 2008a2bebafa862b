#include "net/secure_channel.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace rt::net {
namespace {

constexpr uint8_t kHelloMagic[4] = {'R', 'T', 'H', 'S'};
// Hello: magic 0..3 | version 4..5 | role 6 | reserved 7 | nonce 8..39 | ephemeral public key 40..71.
constexpr size_t kNonceAt = 8, kEphemeralAt = 40;
static_assert(kEphemeralAt + 32 == kHelloSize);

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

void ensure_sodium() {
  static const int result = sodium_init();  // thread-safe, idempotent
  if (result < 0) throw std::runtime_error("libsodium failed to initialise");
}

SessionKey session_key_from_hex(const std::string& hex_in) {
  size_t first = 0, last = hex_in.size();
  while (first < last && std::isspace(uint8_t(hex_in[first]))) ++first;
  while (last > first && std::isspace(uint8_t(hex_in[last - 1]))) --last;
  const std::string hex = hex_in.substr(first, last - first);
  if (hex.size() != 64)
    throw std::invalid_argument("session key: expected 64 hex digits (32 bytes), got " + std::to_string(hex.size()) +
                                " characters");
  SessionKey key;
  for (size_t i = 0; i < 32; ++i) {
    auto digit = [&](char c) -> int {
      if (c >= '0' && c <= '9') return c - '0';
      if (c >= 'a' && c <= 'f') return c - 'a' + 10;
      if (c >= 'A' && c <= 'F') return c - 'A' + 10;
      throw std::invalid_argument(std::string("session key: '") + c + "' is not a hex digit");
    };
    key.bytes[i] = uint8_t(digit(hex[2 * i]) << 4 | digit(hex[2 * i + 1]));
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
  struct stat info {};
  if (::fstat(buffer.fd, &info) != 0 || !S_ISREG(info.st_mode))
    throw std::invalid_argument(name + " is not a regular file");
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
    key = session_key_from_hex(std::string(buffer.bytes.data(), size));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path.string() + ": " + e.what());
  }
  if (is_weak_session_key(key))
    throw std::invalid_argument(name + " holds a weak key (every byte the same): make one with remotetouch keygen FILE");
  if (info.st_mode & (S_IRWXG | S_IRWXO)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", unsigned(info.st_mode & 07777));
    throw std::invalid_argument(name + " is open to the group or others (mode " + mode + "): chmod 600 " + path.string());
  }
  return key;
}

SessionKey write_new_session_key_file(const std::filesystem::path& path) {
  const SessionKey key = random_session_key();
  std::string line = to_hex(key) + "\n";
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
  return std::all_of(key.bytes.begin(), key.bytes.end(), [&](uint8_t b) { return b == key.bytes[0]; });
}

std::string to_hex(const SessionKey& key) {
  char out[65];
  sodium_bin2hex(out, sizeof out, key.bytes.data(), key.bytes.size());
  return out;
}

const char* role_name(Role role) { return role == Role::Connector ? "connector" : "listener"; }

Handshake::Handshake(const SessionKey& key, Role role) : key_(key.bytes), role_(role) {
  ensure_sodium();
  if (is_weak_session_key(key)) throw std::invalid_argument("handshake: a weak session key (every byte the same)");
  randombytes_buf(own_nonce_.data(), own_nonce_.size());
  randombytes_buf(ephemeral_secret_.data(), ephemeral_secret_.size());
  crypto_scalarmult_base(ephemeral_public_.data(), ephemeral_secret_.data());
}

Handshake::Handshake(const SessionKey& key, Role role, const std::array<uint8_t, 32>& nonce) : Handshake(key, role) {
  own_nonce_ = nonce;
}

Handshake::~Handshake() {
  sodium_memzero(ephemeral_secret_.data(), ephemeral_secret_.size());
  wipe();
}

void Handshake::wipe() {
  sodium_memzero(key_.data(), key_.size());
  sodium_memzero(secret_.data(), secret_.size());
  wiped_ = true;
}

std::array<uint8_t, kHelloSize> Handshake::hello() const {
  std::array<uint8_t, kHelloSize> out{};
  std::memcpy(out.data(), kHelloMagic, 4);
  std::memcpy(out.data() + 4, &kHandshakeVersion, 2);
  out[6] = uint8_t(role_);
  out[7] = 0;
  std::memcpy(out.data() + kNonceAt, own_nonce_.data(), 32);
  std::memcpy(out.data() + kEphemeralAt, ephemeral_public_.data(), 32);
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

std::vector<uint8_t> RecordSealer::seal(std::span<const uint8_t> plaintext) {
  std::vector<uint8_t> record(kRecordHeaderSize + plaintext.size() + kRecordTagSize);
  const uint32_t length = uint32_t(plaintext.size() + kRecordTagSize);
  const uint64_t counter = counter_++;
  std::memcpy(record.data(), &length, 4);
  std::memcpy(record.data() + 4, &counter, 8);
  const auto nonce = nonce_of(counter);
  unsigned long long written = 0;
  crypto_aead_xchacha20poly1305_ietf_encrypt(record.data() + kRecordHeaderSize, &written, plaintext.data(),
                                             plaintext.size(), record.data(), kRecordHeaderSize, nullptr, nonce.data(),
                                             key_.data());
  return record;
}

const char* record_error_name(RecordError error) {
  switch (error) {
    case RecordError::None: return "none";
    case RecordError::Oversize: return "record_oversize";
    case RecordError::AuthFailed: return "auth_failed";
    case RecordError::OutOfSequence: return "out_of_sequence";
  }
  return "unknown";
}

RecordError RecordOpener::check_header(std::span<const uint8_t> header, RecordHeader* out, std::string* reason) const {
  std::memcpy(&out->ciphertext_length, header.data(), 4);
  std::memcpy(&out->counter, header.data() + 4, 8);
  if (out->ciphertext_length < kRecordTagSize || out->ciphertext_length > max_plaintext_ + kRecordTagSize) {
    *reason = "record length " + std::to_string(out->ciphertext_length) + " outside " + std::to_string(kRecordTagSize) +
              ".." + std::to_string(max_plaintext_ + kRecordTagSize) + ": the stream is out of step";
    return RecordError::Oversize;
  }
  return RecordError::None;
}

RecordError RecordOpener::open(std::span<const uint8_t> header, std::span<const uint8_t> ciphertext,
                               std::vector<uint8_t>* plaintext, std::string* reason) {
  RecordHeader h;
  if (auto e = check_header(header, &h, reason); e != RecordError::None) return e;
  if (ciphertext.size() != h.ciphertext_length) {
    *reason = "record body of " + std::to_string(ciphertext.size()) + " bytes, header says " + std::to_string(h.ciphertext_length);
    return RecordError::AuthFailed;
  }
  plaintext->resize(ciphertext.size() - kRecordTagSize);
  const auto nonce = nonce_of(h.counter);
  unsigned long long written = 0;
  if (crypto_aead_xchacha20poly1305_ietf_decrypt(plaintext->data(), &written, nullptr, ciphertext.data(), ciphertext.size(),
                                                 header.data(), kRecordHeaderSize, nonce.data(), key_.data()) != 0) {
    plaintext->clear();
    *reason = "record " + std::to_string(h.counter) + " failed authentication (tampered, forged or out of step)";
    return RecordError::AuthFailed;
  }
  if (h.counter != last_ + 1) {
    plaintext->clear();
    *reason = "record " + std::to_string(h.counter) + " out of sequence after " + std::to_string(last_) + " (" +
              (h.counter > last_ ? std::to_string(h.counter - last_ - 1) + " deleted on the way" : "replayed or reordered") + ")";
    return RecordError::OutOfSequence;
  }
  last_ = h.counter;
  return RecordError::None;
}

}  // namespace rt::net
