#pragma once
// A site's events.jsonl: touch start and end, motor pulses, connection changes, each one JSON
// object per line with the site and a monotonic timestamp (microseconds). Thread-safe: the touch
// loop, the network monitor and the display write to it concurrently. Lines are flushed as they
// are written, so a crashed run still leaves what happened before the crash.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace rt::session {

class EventLog {
 public:
  // `site`: "A" or "B", written into every event. Throws if the file cannot be opened.
  EventLog(const std::filesystem::path& path, std::string site);

  // Adds "event", "site" and "t_us" (monotonic microseconds) to `fields` and writes the line.
  void write(const std::string& event, uint64_t t_us, nlohmann::json fields = nlohmann::json::object());
  // Events of this name written so far. Only counts stay in memory, never the events: a long
  // run (or a peer that provokes events) must not grow the process.
  size_t count(const std::string& event) const;

 private:
  mutable std::mutex mutex_;
  std::string site_;
  std::ofstream file_;
  std::map<std::string, size_t> counts_;
};

// Reads an events.jsonl; throws naming the file and line of a line that is not a JSON object.
std::vector<nlohmann::json> read_events(const std::filesystem::path& path);

}  // namespace rt::session
