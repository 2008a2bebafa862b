// Sealed records for the lossy, reordering data channel and the reliable one: replay refused,
// reordering within the window accepted, forgery and another channel's key refused, a record
// behind the window refused, and the strict order refusing a gap.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "net/datagram_seal.h"

using namespace rt::net;

namespace {

std::array<uint8_t, kTrafficKeySize> datagram_test_key(uint8_t seed) {
  std::array<uint8_t, kTrafficKeySize> traffic{};
  for (size_t i = 0; i < traffic.size(); ++i) traffic[i] = uint8_t(seed * 31 + i * 7);
  return datagram_key(traffic, 0);
}

std::vector<uint8_t> datagram_payload(int n) {
  const std::string text = "message " + std::to_string(n);
  return std::vector<uint8_t>(text.begin(), text.end());
}

}  // namespace

TEST_CASE("a sealed datagram opens once, with the message it carried") {
  DatagramSealer sealer(datagram_test_key(1));
  DatagramOpener opener(datagram_test_key(1), DatagramOpener::Order::Window, 1024);
  const auto record = sealer.seal(datagram_payload(1));
  CHECK(record.size() == datagram_payload(1).size() + kDatagramOverhead);
  CHECK(is_sealed_datagram(record));
  std::vector<uint8_t> message;
  std::string why;
  REQUIRE(opener.open(record, &message, &why) == DatagramVerdict::Opened);
  CHECK(message == datagram_payload(1));
  // The very same bytes again: a replay.
  CHECK(opener.open(record, &message, &why) == DatagramVerdict::Replayed);
  CHECK(why.find("opened already") != std::string::npos);
}

TEST_CASE("the window takes records reordered and lost, each once") {
  DatagramSealer sealer(datagram_test_key(2));
  DatagramOpener opener(datagram_test_key(2), DatagramOpener::Order::Window, 1024);
  std::vector<std::vector<uint8_t>> records;
  for (int i = 1; i <= 10; ++i) records.push_back(sealer.seal(datagram_payload(i)));
  std::vector<uint8_t> message;
  std::string why;
  // 5 first, then 2 (late), then 10, then 1 and 7 (late); 3, 4, 6, 8, 9 lost.
  for (const int i : {5, 2, 10, 1, 7}) {
    INFO("record " << i);
    REQUIRE(opener.open(records[size_t(i - 1)], &message, &why) == DatagramVerdict::Opened);
    CHECK(message == datagram_payload(i));
  }
  CHECK(opener.newest_counter() == 10);
  for (const int i : {5, 2, 10, 1, 7}) CHECK(opener.open(records[size_t(i - 1)], &message, &why) == DatagramVerdict::Replayed);
  // A lost one that turns up late still opens, once.
  CHECK(opener.open(records[3], &message, &why) == DatagramVerdict::Opened);
  CHECK(opener.open(records[3], &message, &why) == DatagramVerdict::Replayed);
}

TEST_CASE("a record behind the window is refused, one at its edge taken") {
  DatagramSealer sealer(datagram_test_key(3));
  DatagramOpener opener(datagram_test_key(3), DatagramOpener::Order::Window, 1024);
  std::vector<std::vector<uint8_t>> records;
  for (uint64_t i = 1; i <= kReplayWindow + 2; ++i) records.push_back(sealer.seal(datagram_payload(int(i))));
  std::vector<uint8_t> message;
  std::string why;
  REQUIRE(opener.open(records.back(), &message, &why) == DatagramVerdict::Opened);  // counter kReplayWindow + 2
  // Counter 1 is kReplayWindow + 1 behind: too old; counter 3 is kReplayWindow - 1 behind: taken.
  CHECK(opener.open(records[0], &message, &why) == DatagramVerdict::TooOld);
  CHECK(why.find("beyond the replay window") != std::string::npos);
  CHECK(opener.open(records[1], &message, &why) == DatagramVerdict::TooOld);
  CHECK(opener.open(records[2], &message, &why) == DatagramVerdict::Opened);
  // A jump far ahead clears the window: the records it skipped are not marked as seen.
  DatagramSealer far(datagram_test_key(3));
  for (uint64_t i = 1; i < 5 * kReplayWindow; ++i) far.seal({});
  REQUIRE(opener.open(far.seal(datagram_payload(0)), &message, &why) == DatagramVerdict::Opened);
  CHECK(opener.newest_counter() == 5 * kReplayWindow);
}

TEST_CASE("forged, altered and other keys' records are refused and move nothing") {
  DatagramSealer sealer(datagram_test_key(4));
  DatagramOpener opener(datagram_test_key(4), DatagramOpener::Order::Window, 1024);
  std::vector<uint8_t> message;
  std::string why;
  auto record = sealer.seal(datagram_payload(1));
  for (const size_t at : {size_t(5), kDatagramHeaderSize, record.size() - 1}) {
    auto altered = record;
    altered[at] ^= 0x40;
    INFO("byte " << at);
    CHECK(opener.open(altered, &message, &why) == DatagramVerdict::Forged);
  }
  // A forged counter far ahead must not push the window on: the real record 1 still opens.
  auto ahead = record;
  ahead[4 + 3] = 0x7F;
  CHECK(opener.open(ahead, &message, &why) == DatagramVerdict::Forged);
  CHECK(opener.newest_counter() == 0);
  // The other channel's key (or the other direction's) opens nothing.
  std::array<uint8_t, kTrafficKeySize> traffic{};
  traffic.fill(9);
  DatagramSealer other_channel(datagram_key(traffic, 1));
  DatagramOpener this_channel(datagram_key(traffic, 0), DatagramOpener::Order::Window, 1024);
  CHECK(this_channel.open(other_channel.seal(datagram_payload(1)), &message, &why) == DatagramVerdict::Forged);
  REQUIRE(opener.open(record, &message, &why) == DatagramVerdict::Opened);
  CHECK(message == datagram_payload(1));
}

TEST_CASE("malformed records are refused before any decryption") {
  DatagramSealer sealer(datagram_test_key(5));
  DatagramOpener opener(datagram_test_key(5), DatagramOpener::Order::Window, 16);
  std::vector<uint8_t> message;
  std::string why;
  CHECK(opener.open({}, &message, &why) == DatagramVerdict::Malformed);
  auto record = sealer.seal(datagram_payload(1));
  auto wrong_magic = record;
  wrong_magic[0] = 'X';
  CHECK(opener.open(wrong_magic, &message, &why) == DatagramVerdict::Malformed);
  CHECK(opener.open(std::span(record).first(kDatagramOverhead - 1), &message, &why) == DatagramVerdict::Malformed);
  auto zero = record;
  std::fill(zero.begin() + 4, zero.begin() + 12, uint8_t(0));
  CHECK(opener.open(zero, &message, &why) == DatagramVerdict::Malformed);
  const std::vector<uint8_t> big(17, 1);
  CHECK(opener.open(sealer.seal(big), &message, &why) == DatagramVerdict::Malformed);
  CHECK(why.find("limit") != std::string::npos);
}

TEST_CASE("the strict order takes each record after the last and refuses gaps and repeats") {
  DatagramSealer sealer(datagram_test_key(6));
  DatagramOpener opener(datagram_test_key(6), DatagramOpener::Order::Strict, 1024);
  std::vector<std::vector<uint8_t>> records;
  for (int i = 1; i <= 4; ++i) records.push_back(sealer.seal(datagram_payload(i)));
  std::vector<uint8_t> message;
  std::string why;
  REQUIRE(opener.open(records[0], &message, &why) == DatagramVerdict::Opened);
  CHECK(opener.open(records[2], &message, &why) == DatagramVerdict::OutOfSequence);  // 2 deleted on the way
  CHECK(why.find("deleted") != std::string::npos);
  REQUIRE(opener.open(records[1], &message, &why) == DatagramVerdict::Opened);
  CHECK(opener.open(records[1], &message, &why) == DatagramVerdict::Replayed);
  CHECK(opener.open(records[0], &message, &why) == DatagramVerdict::Replayed);
  REQUIRE(opener.open(records[2], &message, &why) == DatagramVerdict::Opened);
  CHECK(message == datagram_payload(3));
}
