// The motor firmware's line parser (devices/motor/firmware/protocol.c), compiled for the host:
// the same C file the AVR build flashes.
#include <catch2/catch.hpp>

#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "motor/firmware/protocol.h"

namespace {

// Feeds bytes as the UART delivers them and returns the reply line of every completed command.
std::vector<std::string> feed(motor_parser& parser, std::string_view bytes) {
  std::vector<std::string> replies;
  for (const char byte : bytes) {
    motor_command command;
    if (motor_parser_feed(&parser, uint8_t(byte), &command)) {
      char reply[MOTOR_REPLY_MAX + 1];
      const size_t length = motor_format_reply(&command, reply, sizeof reply);
      replies.emplace_back(reply, length);
    }
  }
  return replies;
}

std::vector<std::string> replies_to(std::string_view bytes) {
  motor_parser parser;
  motor_parser_reset(&parser);
  return feed(parser, bytes);
}

std::string reply_to(std::string_view line) {
  const auto replies = replies_to(std::string(line) + "\n");
  REQUIRE(replies.size() == 1);
  return replies[0];
}

motor_command parse_motor_protocol(std::string_view line) { return motor_parse_line(line.data(), line.size()); }

}  // namespace

TEST_CASE("motor protocol: valid commands are parsed and echoed", "[motor][protocol]") {
  const motor_command pulse = parse_motor_protocol("P 120 200");
  CHECK(pulse.kind == MOTOR_COMMAND_PULSE);
  CHECK(pulse.duration_ms == 120);
  CHECK(pulse.strength == 200);
  CHECK(reply_to("P 120 200") == "OK P 120 200");
  CHECK(parse_motor_protocol("S").kind == MOTOR_COMMAND_STOP);
  CHECK(reply_to("S") == "OK S");
  CHECK(parse_motor_protocol("V").kind == MOTOR_COMMAND_VERSION);
  CHECK(reply_to("V") == "OK V remotetouch-motor 1");

  // Spaces are separators however many; leading zeros are still the same number.
  CHECK(reply_to("  P   7    009  ") == "OK P 7 9");
  // '\r' also ends a line, so "\r\n" from a terminal gives one reply, not two.
  CHECK(replies_to("S\r\nV\r\n") == std::vector<std::string>{"OK S", "OK V remotetouch-motor 1"});
  CHECK(replies_to("\n\n   \n\r\n").empty());

  char ready[MOTOR_REPLY_MAX + 1];
  CHECK(std::string(ready, motor_format_ready(ready, sizeof ready)) == "READY remotetouch-motor 1");
}

TEST_CASE("motor protocol: every bound is inclusive and enforced, never clamped", "[motor][protocol]") {
  CHECK(reply_to("P 1 1") == "OK P 1 1");
  CHECK(reply_to("P 1000 255") == "OK P 1000 255");
  CHECK(reply_to("P 0 100") == "ERR duration 0 ms out of range 1..1000");
  CHECK(reply_to("P 1001 100") == "ERR duration 1001 ms out of range 1..1000");
  CHECK(reply_to("P 100 0") == "ERR strength 0 out of range 1..255");
  CHECK(reply_to("P 100 256") == "ERR strength 256 out of range 1..255");
  CHECK(reply_to("P 999999999 1") == "ERR duration 999999999 ms out of range 1..1000");
  CHECK(reply_to("P 10 999999999") == "ERR strength 999999999 out of range 1..255");
  CHECK(reply_to("P 1234567890 1") == "ERR number longer than 9 digits");
  // Duration is checked first: both out of range reports the duration.
  CHECK(reply_to("P 0 0") == "ERR duration 0 ms out of range 1..1000");

  const motor_command rejected = parse_motor_protocol("P 5000 10");
  CHECK(rejected.kind == MOTOR_COMMAND_REJECTED);
  CHECK(rejected.error == MOTOR_ERROR_DURATION_RANGE);
  CHECK(rejected.bad_value == 5000);

  CHECK(motor_pulse_in_bounds(1, 1));
  CHECK(motor_pulse_in_bounds(1000, 255));
  CHECK_FALSE(motor_pulse_in_bounds(0, 1));
  CHECK_FALSE(motor_pulse_in_bounds(1001, 1));
  CHECK_FALSE(motor_pulse_in_bounds(1, 0));
  CHECK_FALSE(motor_pulse_in_bounds(1, 256));
}

TEST_CASE("motor protocol: malformed commands say what is wrong", "[motor][protocol]") {
  const std::string pulse_syntax = "ERR syntax: expected P <duration_ms> <strength>";
  for (const char* line : {"P", "P 10", "P 10 20 30", "P -5 10", "P +5 10", "P 12x 10", "P 0x10 10", "P 10 20x",
                           "P 1.5 10"}) {
    INFO(line);
    CHECK(reply_to(line) == pulse_syntax);
  }
  CHECK(reply_to("S 1") == "ERR syntax: S takes no arguments");
  CHECK(reply_to("V now") == "ERR syntax: V takes no arguments");
  CHECK(reply_to("X") == "ERR unknown command 'X': expected P, S or V");
  CHECK(reply_to("p 10 10") == "ERR unknown command 'p': expected P, S or V");
  CHECK(reply_to("P10 10") == "ERR unknown command 'P10': expected P, S or V");
  CHECK(reply_to("STOP") == "ERR unknown command 'STOP': expected P, S or V");
  CHECK(reply_to("ABCDEFGHIJKL 1") == "ERR unknown command 'ABCDEFGH': expected P, S or V");
}

TEST_CASE("motor protocol: garbage bytes reject their line and the next line parses", "[motor][protocol]") {
  CHECK(replies_to(std::string("P 10\x01 20\nS\n")) ==
        std::vector<std::string>{"ERR byte 0x01 is not printable ASCII", "OK S"});
  CHECK(replies_to(std::string("\xff\xfe\nV\n")) ==
        std::vector<std::string>{"ERR byte 0xFF is not printable ASCII", "OK V remotetouch-motor 1"});
  CHECK(replies_to(std::string("S\0\n", 3)) == std::vector<std::string>{"ERR byte 0x00 is not printable ASCII"});
  // Only the first fault of a line is reported.
  CHECK(replies_to(std::string("\x1b[31m") + std::string(40, 'x') + "\n") ==
        std::vector<std::string>{"ERR byte 0x1B is not printable ASCII"});
}

TEST_CASE("motor protocol: overlong lines are rejected whole, then parsing resumes", "[motor][protocol]") {
  // 32 bytes is the limit: a valid pulse padded to exactly 32 bytes is still accepted.
  std::string longest = "P 000000100 000000200";
  longest.resize(MOTOR_LINE_MAX, ' ');
  CHECK(reply_to(longest) == "OK P 100 200");
  CHECK(reply_to(longest + " ") == "ERR line longer than 32 bytes");
  CHECK(replies_to(std::string(500, 'P') + "\nP 50 60\n") ==
        std::vector<std::string>{"ERR line longer than 32 bytes", "OK P 50 60"});
}

TEST_CASE("motor protocol: lines split across reads are assembled", "[motor][protocol]") {
  motor_parser parser;
  motor_parser_reset(&parser);
  CHECK(feed(parser, "P 1").empty());
  CHECK(feed(parser, "20 2").empty());
  CHECK(feed(parser, "00").empty());
  CHECK(feed(parser, "\nS") == std::vector<std::string>{"OK P 120 200"});
  CHECK(feed(parser, "\r") == std::vector<std::string>{"OK S"});
  CHECK(feed(parser, "\n").empty());

  // Any split of a stream gives the replies of the whole stream.
  const std::string stream = "P 10 20\nX\nS\r\nP 1001 5\nV\n";
  const auto whole = replies_to(stream);
  REQUIRE(whole.size() == 5);
  for (size_t cut = 0; cut <= stream.size(); ++cut) {
    motor_parser split;
    motor_parser_reset(&split);
    auto replies = feed(split, stream.substr(0, cut));
    const auto rest = feed(split, stream.substr(cut));
    replies.insert(replies.end(), rest.begin(), rest.end());
    INFO("cut at " << cut);
    CHECK(replies == whole);
  }
}

TEST_CASE("motor protocol: a receive overrun loses the line, not the stream", "[motor][protocol]") {
  motor_parser parser;
  motor_parser_reset(&parser);
  CHECK(feed(parser, "P 10").empty());
  motor_parser_mark_overrun(&parser);
  CHECK(feed(parser, " 20\nS\n") ==
        std::vector<std::string>{"ERR receive overrun: line lost, send it again", "OK S"});
}

TEST_CASE("motor protocol: random bytes never give a reply outside the protocol", "[motor][protocol]") {
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> printable(0x20, 0x7e);
  motor_parser parser;
  motor_parser_reset(&parser);
  size_t replies = 0;
  for (int i = 0; i < 200000; ++i) {
    // Mostly command letters, digits and spaces, some line ends and some of any byte, so that
    // every parser path is taken.
    static const std::string likely = "PSV 0123456789";
    const unsigned pick = rng() % 16;
    uint8_t value = uint8_t(printable(rng));
    if (pick == 0) value = '\n';
    if (pick == 1) value = uint8_t(byte(rng));
    if (pick >= 2 && pick < 9) value = uint8_t(likely[rng() % likely.size()]);
    motor_command command;
    if (!motor_parser_feed(&parser, value, &command)) continue;
    ++replies;
    char reply[MOTOR_REPLY_MAX + 1];
    const size_t length = motor_format_reply(&command, reply, sizeof reply);
    const std::string text(reply, length);
    REQUIRE(length <= MOTOR_REPLY_MAX);
    REQUIRE(text.find('\n') == std::string::npos);
    REQUIRE((text.rfind("OK ", 0) == 0 || text.rfind("ERR ", 0) == 0));
    if (command.kind == MOTOR_COMMAND_PULSE) REQUIRE(motor_pulse_in_bounds(command.duration_ms, command.strength));
  }
  CHECK(replies > 1000);
}
