#include "sim/tracker_replay.h"

#include <string>

#include "config/json.h"
#include "sim/leap_json.h"

namespace rt::sim {

using config::JsonError;

namespace {

enum class LineRead { Line, End, TooLong };

// std::getline with a bound: a file without newlines must not grow the string without limit.
LineRead read_line(std::istream& in, std::string& line, size_t max_bytes) {
  line.clear();
  std::streambuf& buffer = *in.rdbuf();
  for (;;) {
    const int c = buffer.sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return line.empty() ? LineRead::End : LineRead::Line;
    }
    if (c == '\n') return LineRead::Line;
    if (line.size() >= max_bytes) return LineRead::TooLong;
    line.push_back(char(c));
  }
}

}  // namespace

ReplayHandTracker::ReplayHandTracker(const std::filesystem::path& path) : path_(path), file_(path) {
  if (!file_) throw JsonError("cannot open tracker recording '" + path.string() + "'");
}

std::optional<TrackerFrame> ReplayHandTracker::next_frame() {
  std::string line;
  for (;;) {
    const LineRead read = read_line(file_, line, kMaxLineBytes);
    if (read == LineRead::End) break;
    ++line_number_;
    if (read == LineRead::TooLong)
      throw JsonError("'" + path_.string() + "' line " + std::to_string(line_number_) + ": longer than " +
                      std::to_string(kMaxLineBytes) + " bytes, not a tracker frame");
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    // Appended piecewise: GCC 12's -Wrestrict misfires on "literal" + std::string at -O3.
    std::string where = "'";
    where.append(path_.string()).append("' line ").append(std::to_string(line_number_));
    TrackerFrame frame;
    try {
      frame = parse_leap_json_line(line);
    } catch (const JsonError& error) {
      throw JsonError(where + ": " + error.what());
    }
    if (last_timestamp_us_ && frame.timestamp_us < *last_timestamp_us_)
      throw JsonError(where + ": timestamp " + std::to_string(frame.timestamp_us) + " goes back in time (previous " +
                      std::to_string(*last_timestamp_us_) + ")");
    last_timestamp_us_ = frame.timestamp_us;
    return frame;
  }
  if (file_.bad()) throw JsonError("reading '" + path_.string() + "' failed after line " + std::to_string(line_number_));
  return std::nullopt;
}

uint64_t check_tracker_recording(const std::filesystem::path& path) {
  ReplayHandTracker replay(path);
  uint64_t frames = 0;
  while (replay.next_frame()) ++frames;
  return frames;
}

uint64_t record_tracker_jsonl(HandTracker& tracker, const std::filesystem::path& path) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream file(path);
  if (!file) throw JsonError("cannot write '" + path.string() + "'");
  uint64_t count = 0;
  while (const std::optional<TrackerFrame> frame = tracker.next_frame()) {
    file << leap_json_line(*frame) << '\n';
    ++count;
  }
  file.flush();
  if (!file) throw JsonError("writing '" + path.string() + "' failed");
  return count;
}

}  // namespace rt::sim
