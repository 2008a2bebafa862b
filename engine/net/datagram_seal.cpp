#include "net/datagram_seal.h"

#include <sodium.h>

#include <algorithm>
#include <cstring>


namespace rt::net {
namespace {

constexpr char kDatagramKdfContext[crypto_kdf_CONTEXTBYTES + 1] = "RTDgram1";

std::array<uint8_t, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES> datagram_nonce(uint64_t counter) {
  std::array<uint8_t, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES> nonce{};
  for (size_t i = 0; i < 8; ++i) nonce[i] = uint8_t(counter >> (8 * i));
  return nonce;
}

uint64_t datagram_counter(std::span<const uint8_t> record) {
  uint64_t counter = 0;
  for (size_t i = 0; i < 8; ++i) counter |= uint64_t(record[4 + i]) << (8 * i);
  return counter;
}

}  // namespace

bool is_sealed_datagram(std::span<const uint8_t> bytes) {
  return bytes.size() >= sizeof(kDatagramMagic) && std::memcmp(bytes.data(), kDatagramMagic, sizeof(kDatagramMagic)) == 0;
}

std::array<uint8_t, kTrafficKeySize> datagram_key(const std::array<uint8_t, kTrafficKeySize>& traffic_key, uint64_t channel) {
  ensure_sodium();
  std::array<uint8_t, kTrafficKeySize> key{};
  crypto_kdf_derive_from_key(key.data(), key.size(), channel, kDatagramKdfContext, traffic_key.data());
  return key;
}

DatagramSealer::~DatagramSealer() { sodium_memzero(key_.data(), key_.size()); }

std::vector<uint8_t> DatagramSealer::seal(std::span<const uint8_t> message) {
  std::vector<uint8_t> record(kDatagramOverhead + message.size());
  std::memcpy(record.data(), kDatagramMagic, sizeof(kDatagramMagic));
  const uint64_t counter = counter_++;
  for (size_t i = 0; i < 8; ++i) record[4 + i] = uint8_t(counter >> (8 * i));
  const auto nonce = datagram_nonce(counter);
  unsigned long long written = 0;
  crypto_aead_xchacha20poly1305_ietf_encrypt(record.data() + kDatagramHeaderSize, &written, message.data(), message.size(),
                                             record.data(), kDatagramHeaderSize, nullptr, nonce.data(), key_.data());
  return record;
}

const char* datagram_verdict_name(DatagramVerdict verdict) {
  switch (verdict) {
    case DatagramVerdict::Opened: return "opened";
    case DatagramVerdict::Malformed: return "malformed";
    case DatagramVerdict::Forged: return "forged";
    case DatagramVerdict::Replayed: return "replayed";
    case DatagramVerdict::TooOld: return "too_old";
    case DatagramVerdict::OutOfSequence: return "out_of_sequence";
  }
  return "unknown";
}

DatagramOpener::DatagramOpener(const std::array<uint8_t, kTrafficKeySize>& key, Order order, size_t max_message)
    : key_(key), order_(order), max_message_(max_message) {}

DatagramOpener::~DatagramOpener() { sodium_memzero(key_.data(), key_.size()); }

bool DatagramOpener::seen(uint64_t counter) const {
  const uint64_t bit = counter % kReplayWindow;
  return (window_[bit / 64] >> (bit % 64)) & 1u;
}

void DatagramOpener::mark(uint64_t counter) {
  if (counter > newest_) {
    // The counters skipped over were never opened: their bits, left from a window ago, are cleared.
    if (counter - newest_ >= kReplayWindow) {
      window_.fill(0);
    } else {
      for (uint64_t c = newest_ + 1; c < counter; ++c) {
        const uint64_t bit = c % kReplayWindow;
        window_[bit / 64] &= ~(uint64_t(1) << (bit % 64));
      }
    }
    newest_ = counter;
  }
  const uint64_t bit = counter % kReplayWindow;
  window_[bit / 64] |= uint64_t(1) << (bit % 64);
}

DatagramVerdict DatagramOpener::open(std::span<const uint8_t> record, std::vector<uint8_t>* message, std::string* reason) {
  auto refuse = [&](DatagramVerdict verdict, const std::string& why) {
    if (reason) *reason = why;
    return verdict;
  };
  if (record.size() < kDatagramOverhead || !is_sealed_datagram(record))
    return refuse(DatagramVerdict::Malformed, "not a sealed record (" + std::to_string(record.size()) + " bytes)");
  if (record.size() - kDatagramOverhead > max_message_)
    return refuse(DatagramVerdict::Malformed, "a sealed record of " + std::to_string(record.size()) + " bytes, over the " +
                                                  std::to_string(max_message_) + "-byte limit");
  const uint64_t counter = datagram_counter(record);
  if (counter == 0) return refuse(DatagramVerdict::Malformed, "a sealed record with counter 0");
  // What the counter alone refuses is refused before any decryption is spent on it.
  if (order_ == Order::Strict && counter <= newest_)
    return refuse(DatagramVerdict::Replayed, "record " + std::to_string(counter) + " again (last " + std::to_string(newest_) + ")");
  if (order_ == Order::Strict && counter != newest_ + 1)
    return refuse(DatagramVerdict::OutOfSequence,
                  "record " + std::to_string(counter) + " after " + std::to_string(newest_) + ": records were deleted on the way");
  if (order_ == Order::Window && counter <= newest_ && newest_ - counter >= kReplayWindow)
    return refuse(DatagramVerdict::TooOld, "record " + std::to_string(counter) + " is " + std::to_string(newest_ - counter) +
                                               " behind the newest, beyond the replay window of " + std::to_string(kReplayWindow));
  if (order_ == Order::Window && counter <= newest_ && seen(counter))
    return refuse(DatagramVerdict::Replayed, "record " + std::to_string(counter) + " was opened already");
  std::vector<uint8_t> plain(record.size() - kDatagramOverhead);
  const auto nonce = datagram_nonce(counter);
  unsigned long long written = 0;
  if (crypto_aead_xchacha20poly1305_ietf_decrypt(plain.data(), &written, nullptr, record.data() + kDatagramHeaderSize,
                                                 record.size() - kDatagramHeaderSize, record.data(), kDatagramHeaderSize,
                                                 nonce.data(), key_.data()) != 0)
    return refuse(DatagramVerdict::Forged, "a record that does not authenticate (forged, altered, or another key's)");
  mark(counter);
  if (message) *message = std::move(plain);
  return DatagramVerdict::Opened;
}

}  // namespace rt::net
