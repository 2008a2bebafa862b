#include "session/event_log.h"

#include <stdexcept>

namespace rt::session {

EventLog::EventLog(const std::filesystem::path& path, std::string site) : site_(std::move(site)), file_(path) {
  if (!file_) throw std::runtime_error("cannot write the event log " + path.string());
}

void EventLog::write(const std::string& event, uint64_t t_us, nlohmann::json fields) {
  if (!fields.is_object()) fields = nlohmann::json::object();
  fields["event"] = event;
  fields["site"] = site_;
  fields["t_us"] = t_us;
  std::lock_guard lock(mutex_);
  file_ << fields.dump() << "\n";
  file_.flush();
  ++counts_[event];
}

size_t EventLog::count(const std::string& event) const {
  std::lock_guard lock(mutex_);
  const auto found = counts_.find(event);
  return found == counts_.end() ? 0 : found->second;
}

std::vector<nlohmann::json> read_events(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot read the event log " + path.string());
  std::vector<nlohmann::json> events;
  std::string line;
  for (size_t number = 1; std::getline(file, line); ++number) {
    if (line.empty()) continue;
    nlohmann::json event = nlohmann::json::parse(line, nullptr, false);
    if (event.is_discarded() || !event.is_object())
      throw std::runtime_error(path.string() + ":" + std::to_string(number) + ": not a JSON object");
    events.push_back(std::move(event));
  }
  return events;
}

}  // namespace rt::session
