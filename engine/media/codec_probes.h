#pragma once
// What the call's codecs cost and ask, measured by pad probes on their elements: milliseconds from
// a picture entering an encoder or decoder to its leaving (matched by presentation time where the
// element keeps it, else by order), and the keyframes asked (force-key-unit events going upstream: a depayloader that lost a
// picture asks its sender, through RTCP, for a new one). A CPU module on GStreamer only.
#include <gst/gst.h>

#include <array>
#include <cstdint>
#include <mutex>

namespace rt::media {

class CodecClock {
 public:
  // Times `element` from its "sink" pad to its "src" pad. The clock must outlive the element.
  void attach(GstElement* element);
  // Median and 90th percentile over the last kSamples pictures; 0 when none.
  double median_ms() const;
  double p90_ms() const;
  uint64_t pictures() const;

 private:
  static constexpr size_t kPending = 32, kSamples = 512;
  void entered(GstClockTime pts);
  void left(GstClockTime pts);
  double percentile_ms(double q) const;

  mutable std::mutex mutex_;
  std::array<std::pair<GstClockTime, uint64_t>, kPending> pending_{};  // pts, monotonic µs on entering
  size_t next_pending_ = 0;
  GstClockTime last_left_pts_ = GST_CLOCK_TIME_NONE;
  std::array<float, kSamples> samples_{};
  uint64_t count_ = 0;
};

// Counts the force-key-unit events that go upstream through `pad`. The counter must outlive it.
class KeyframeRequests {
 public:
  void attach(GstPad* pad);
  uint64_t count() const;

 private:
  mutable std::mutex mutex_;
  uint64_t count_ = 0;
};

}  // namespace rt::media
