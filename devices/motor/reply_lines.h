#pragma once
// Splits what the board sends into lines. USB packets cut lines anywhere, so bytes are kept
// until a line end arrives. A line with a byte outside printable ASCII, or longer than the
// firmware ever sends, is garbage (wrong baud rate, other firmware, a glitch): it comes out as
// an error that says what was wrong as soon as it is seen, and reading resynchronises at the
// next line end.
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace rt::motor {

struct ReplyLine {
  std::string text;   // without the line end
  std::string error;  // non-empty when the line is garbage
};

class ReplyLines {
 public:
  void append(std::span<const uint8_t> bytes);
  std::optional<ReplyLine> next();
  void clear();

 private:
  std::string current_;
  bool skipping_ = false;  // inside a garbage line, until its line end
  std::deque<ReplyLine> lines_;
};

// Printable ASCII as is, anything else as \xNN, at most `limit` bytes shown: for messages
// that quote what the device sent.
std::string quote_bytes(std::string_view bytes, size_t limit = 80);

}  // namespace rt::motor
