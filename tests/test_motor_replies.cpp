// Splitting the board's output into reply lines, and rejecting garbage with a reason.
#include <catch2/catch.hpp>

#include <string>

#include "motor/reply_lines.h"

using rt::motor::quote_bytes;
using rt::motor::ReplyLines;

namespace {

void append(ReplyLines& lines, const std::string& bytes) {
  lines.append(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
}

}  // namespace

TEST_CASE("reply lines: packets cut lines anywhere", "[motor][replies]") {
  ReplyLines lines;
  append(lines, "OK P 1");
  CHECK_FALSE(lines.next());
  append(lines, "20 200\nOK");
  auto first = lines.next();
  REQUIRE(first);
  CHECK(first->text == "OK P 120 200");
  CHECK(first->error.empty());
  CHECK_FALSE(lines.next());
  append(lines, " S\r\n\r\nREADY remotetouch-motor 1\n");
  CHECK(lines.next()->text == "OK S");
  CHECK(lines.next()->text == "READY remotetouch-motor 1");
  CHECK_FALSE(lines.next());
}

TEST_CASE("reply lines: garbage is reported at once, then lines resume", "[motor][replies]") {
  ReplyLines lines;
  append(lines, std::string("OK\x01 still garbage"));
  auto bad = lines.next();
  REQUIRE(bad);
  CHECK(bad->error == "byte 0x01 is not printable ASCII");
  CHECK(bad->text == "OK\x01");
  append(lines, " more garbage\xff\nOK S\n");
  auto good = lines.next();
  REQUIRE(good);
  CHECK(good->error.empty());
  CHECK(good->text == "OK S");

  append(lines, std::string(64, 'A'));
  auto overlong = lines.next();
  REQUIRE(overlong);
  CHECK(overlong->error == "line longer than 63 bytes");
  append(lines, std::string(1000, 'A') + "\nOK V remotetouch-motor 1\n");
  CHECK(lines.next()->text == "OK V remotetouch-motor 1");
  CHECK_FALSE(lines.next());

  append(lines, "half a li");
  lines.clear();
  append(lines, "ne\nOK S\n");
  CHECK(lines.next()->text == "ne");  // clear() dropped the first half; what follows is kept
  CHECK(lines.next()->text == "OK S");
}

TEST_CASE("reply lines: quoting shows what arrived without control bytes", "[motor][replies]") {
  CHECK(quote_bytes("OK S") == "OK S");
  CHECK(quote_bytes(std::string("A\x00\n\\", 4)) == "A\\x00\\x0A\\x5C");
  CHECK(quote_bytes(std::string(100, 'x'), 10) == "xxxxxxxxxx...");
}
