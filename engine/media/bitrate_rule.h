#pragma once
// The encoder's bitrate under a real network, from what the other peer's RTCP receiver reports
// say of our stream: its loss over the last report interval and the round trip. A loss-based
// rule of the kind WebRTC's own controller starts from (no transport-wide feedback): lower the
// rate quickly when the receiver loses more than it should, raise it slowly while the path is
// clean, hold it in between. Pure logic: the caller reads the reports and sets the encoder.
#include <cstdint>
#include <string>

namespace rt::media {

struct BitrateRuleOptions {
  int start_kbps = 2500;
  int floor_kbps = 300;
  int ceiling_kbps = 2500;  // the start: a clean path keeps the call within its budget (docs/webrtc.md)
  double loss_high = 0.02;   // above: lower the rate
  double loss_clean = 0.01;  // below (and a short round trip): raise it
  double round_trip_high_s = 0.4;  // above: the path is queueing; lower as for loss
  double lower_factor = 0.85;      // per report above loss_high
  double raise_factor = 1.05;      // per clean report: about a fifth more in four reports
};

// Empty when the options can be used, else what is wrong with them.
std::string check_bitrate_rule(const BitrateRuleOptions& options);

class BitrateRule {
 public:
  explicit BitrateRule(BitrateRuleOptions options);
  // One receiver report: the fraction of our packets it lost since its last report (0..1) and the
  // round trip in seconds (negative when not known). Returns the rate the encoder should now run at.
  int on_report(double fraction_lost, double round_trip_s);
  int kbps() const { return kbps_; }
  uint64_t lowered() const { return lowered_; }
  uint64_t raised() const { return raised_; }

 private:
  BitrateRuleOptions options_;
  double rate_ = 0;  // kept unrounded, so that small raises add up
  int kbps_ = 0;
  uint64_t lowered_ = 0, raised_ = 0;
};

}  // namespace rt::media
