#include "tracker/leap_recorder.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "sim/leap_json.h"

namespace rt::devices {
namespace {

// Faster than any Leap service sends (about 120 frames a second), so that few are replaced unseen.
constexpr auto kLeapPollPeriod = std::chrono::milliseconds(1);

}  // namespace

LeapRecorder::LeapRecorder(const LeapServiceTracker& service, std::filesystem::path arrivals)
    : service_(service), arrivals_path_(std::move(arrivals)), arrivals_(arrivals_path_) {
  if (!arrivals_) throw std::runtime_error("record: cannot write '" + arrivals_path_.string() + "'");
  thread_ = std::thread([this] { poll(); });
}

LeapRecorder::~LeapRecorder() { stop(); }

void LeapRecorder::stop() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
}

void LeapRecorder::poll() {
  uint64_t last_sequence = 0, last_arrival_us = 0;
  while (!stopping_) {
    if (const std::optional<LeapServiceTracker::Received> received = service_.newest();
        received && received->sequence > last_sequence && received->received_us > last_arrival_us) {
      // The frames before the first one polled came before the recording.
      if (last_sequence > 0) missed_ += received->sequence - last_sequence - 1;
      last_sequence = received->sequence;
      last_arrival_us = received->received_us;
      sim::TrackerFrame frame = received->frame;
      frame.timestamp_us = received->received_us;
      arrivals_ << sim::leap_json_line(frame) << '\n';
    }
    std::this_thread::sleep_for(kLeapPollPeriod);
  }
  arrivals_.flush();
}

LeapRecording LeapRecorder::finish(const std::filesystem::path& tracker_jsonl, int64_t host_minus_device_us) {
  stop();
  arrivals_.close();
  std::ifstream in(arrivals_path_);
  std::ofstream out(tracker_jsonl);
  if (!in || !out) throw std::runtime_error("record: cannot write '" + tracker_jsonl.string() + "'");
  LeapRecording recording;
  recording.frames_missed = missed_;
  std::string line;
  uint64_t last_us = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    sim::TrackerFrame frame = sim::parse_leap_json_line(line);
    const int64_t device_us = int64_t(frame.timestamp_us) - host_minus_device_us;
    // Frames from before the cameras' clock started, or arriving together, have no place in it.
    if (device_us <= 0 || (recording.frames > 0 && uint64_t(device_us) <= last_us)) continue;
    frame.timestamp_us = uint64_t(device_us);
    last_us = frame.timestamp_us;
    out << sim::leap_json_line(frame) << '\n';
    ++recording.frames;
    if (!frame.hands.empty()) ++recording.frames_with_hands;
  }
  if (!out) throw std::runtime_error("record: writing '" + tracker_jsonl.string() + "' failed");
  in.close();
  std::error_code ignored;
  std::filesystem::remove(arrivals_path_, ignored);
  return recording;
}

}  // namespace rt::devices
