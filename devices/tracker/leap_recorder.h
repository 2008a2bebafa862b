#pragma once
// `record --tracker leap`: the Leap service's frames written beside the cameras' recordings as
// tracker.jsonl, so that a recorded call replays with its hands. The service stamps its frames
// on its own clock, which nothing else shares; each frame is therefore stamped when it arrives on
// this machine's monotonic clock, and when the recording ends those times are moved onto the
// cameras' device clock by the offset the camera recorder measured (the smallest arrival-minus-
// device time of its captures). What stays is the difference of the two devices' delivery delays.
//
// Frames go to a file as they arrive (a long recording is never held in memory), then are
// rewritten once with the cameras' times.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <thread>

#include "tracker/leap_service.h"

namespace rt::devices {

struct LeapRecording {
  uint64_t frames = 0;          // written to tracker.jsonl
  uint64_t frames_missed = 0;   // sent by the service but replaced before they were polled
  uint64_t frames_with_hands = 0;
};

class LeapRecorder {
 public:
  // Starts polling `service` (which must outlive the recorder) on a thread of its own, writing
  // each new frame to `arrivals` with its arrival time. Throws std::runtime_error when the file
  // cannot be made.
  LeapRecorder(const LeapServiceTracker& service, std::filesystem::path arrivals);
  ~LeapRecorder();  // stops polling
  LeapRecorder(const LeapRecorder&) = delete;
  LeapRecorder& operator=(const LeapRecorder&) = delete;

  // Stops polling, writes `tracker_jsonl` with every frame's time moved onto the cameras' clock
  // (arrival - host_minus_device_us), dropping a frame that would come before zero or not after
  // the one before, and removes the arrivals file.
  LeapRecording finish(const std::filesystem::path& tracker_jsonl, int64_t host_minus_device_us);

 private:
  void poll();
  void stop();

  const LeapServiceTracker& service_;
  std::filesystem::path arrivals_path_;
  std::ofstream arrivals_;
  std::atomic<bool> stopping_{false};
  uint64_t missed_ = 0;  // the poller's; read after it stopped
  std::thread thread_;
};

}  // namespace rt::devices
