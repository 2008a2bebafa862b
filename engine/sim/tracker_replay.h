#pragma once
// Replays a recorded tracker.jsonl (Leap v6 JSON, one frame per line) as a HandTracker, and
// records one: what the replay returns equals what was recorded, bit for bit.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>

#include "sim/hand_tracker.h"

namespace rt::sim {

class ReplayHandTracker : public HandTracker {
 public:
  // Far more than any frame of two hands (a few kB): a longer line is refused, never buffered.
  static constexpr size_t kMaxLineBytes = size_t(1) << 20;

  // Throws config::JsonError when the file cannot be opened.
  explicit ReplayHandTracker(const std::filesystem::path& path);
  // Throws config::JsonError naming the file and line for a malformed frame, a line over
  // kMaxLineBytes, or a frame whose timestamp goes backwards. Blank lines are skipped.
  std::optional<TrackerFrame> next_frame() override;

 private:
  std::filesystem::path path_;
  std::ifstream file_;
  uint64_t line_number_ = 0;
  std::optional<uint64_t> last_timestamp_us_;
};

// Reads the whole recording once and returns its frame count, so that a site refuses a bad one
// before it connects rather than in the middle of a session. Throws as next_frame does.
uint64_t check_tracker_recording(const std::filesystem::path& path);

// Writes every frame of `tracker` to `path`, one per line; returns how many.
uint64_t record_tracker_jsonl(HandTracker& tracker, const std::filesystem::path& path);

}  // namespace rt::sim
