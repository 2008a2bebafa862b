#include "motor/reply_lines.h"

#include <cstdio>

#include "motor/firmware/protocol.h"

namespace rt::motor {

void ReplyLines::append(std::span<const uint8_t> bytes) {
  for (const uint8_t byte : bytes) {
    if (byte == '\n' || byte == '\r') {
      if (!current_.empty() && !skipping_) lines_.push_back(ReplyLine{current_, {}});
      current_.clear();
      skipping_ = false;
      continue;
    }
    if (skipping_) continue;
    current_.push_back(char(byte));
    // Reported as soon as it is seen, so a caller waiting for a reply learns of the garbage
    // now rather than at its timeout; the rest of the line is dropped.
    std::string error;
    if (byte < 0x20 || byte > 0x7e) {
      char hex[5];
      std::snprintf(hex, sizeof hex, "0x%02X", unsigned(byte));
      error = std::string("byte ") + hex + " is not printable ASCII";
    } else if (current_.size() > MOTOR_REPLY_MAX) {
      error = "line longer than " + std::to_string(MOTOR_REPLY_MAX) + " bytes";
    }
    if (!error.empty()) {
      lines_.push_back(ReplyLine{current_, error});
      current_.clear();
      skipping_ = true;
    }
  }
}

std::optional<ReplyLine> ReplyLines::next() {
  if (lines_.empty()) return std::nullopt;
  ReplyLine line = std::move(lines_.front());
  lines_.pop_front();
  return line;
}

void ReplyLines::clear() {
  current_.clear();
  skipping_ = false;
  lines_.clear();
}

std::string quote_bytes(std::string_view bytes, size_t limit) {
  std::string quoted;
  for (size_t i = 0; i < bytes.size() && i < limit; ++i) {
    const auto byte = uint8_t(bytes[i]);
    if (byte >= 0x20 && byte <= 0x7e && byte != '\\') {
      quoted.push_back(char(byte));
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02X", unsigned(byte));
      quoted += hex;
    }
  }
  if (bytes.size() > limit) quoted += "...";
  return quoted;
}

}  // namespace rt::motor
