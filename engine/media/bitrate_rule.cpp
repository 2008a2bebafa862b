#include "media/bitrate_rule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt::media {

std::string check_bitrate_rule(const BitrateRuleOptions& o) {
  if (o.floor_kbps < 50 || o.ceiling_kbps < o.floor_kbps || o.ceiling_kbps > 100'000)
    return "the bitrate's floor must be at least 50 kbit/s and its ceiling between the floor and 100000 kbit/s (floor " +
           std::to_string(o.floor_kbps) + ", ceiling " + std::to_string(o.ceiling_kbps) + ")";
  if (o.start_kbps < o.floor_kbps || o.start_kbps > o.ceiling_kbps)
    return "the starting bitrate " + std::to_string(o.start_kbps) + " kbit/s is outside its floor and ceiling (" +
           std::to_string(o.floor_kbps) + ".." + std::to_string(o.ceiling_kbps) + ")";
  if (!(o.loss_clean >= 0 && o.loss_clean <= o.loss_high && o.loss_high < 1))
    return "the bitrate rule's loss thresholds must satisfy 0 <= clean <= high < 1";
  if (!(o.round_trip_high_s > 0) || !(o.lower_factor > 0 && o.lower_factor < 1) || !(o.raise_factor > 1 && o.raise_factor < 2))
    return "the bitrate rule's round trip must be positive, its lowering factor in (0, 1) and its raising factor in (1, 2)";
  return {};
}

BitrateRule::BitrateRule(BitrateRuleOptions options) : options_(options) {
  if (const std::string why = check_bitrate_rule(options_); !why.empty()) throw std::invalid_argument(why);
  rate_ = options_.start_kbps;
  kbps_ = options_.start_kbps;
}

int BitrateRule::on_report(double fraction_lost, double round_trip_s) {
  // A report that says nothing usable changes nothing.
  if (!std::isfinite(fraction_lost) || fraction_lost < 0 || fraction_lost > 1) return kbps_;
  const bool queueing = std::isfinite(round_trip_s) && round_trip_s > options_.round_trip_high_s;
  if (fraction_lost > options_.loss_high || queueing) {
    rate_ *= options_.lower_factor;
    ++lowered_;
  } else if (fraction_lost < options_.loss_clean) {
    if (rate_ < options_.ceiling_kbps) ++raised_;
    rate_ *= options_.raise_factor;
  }
  rate_ = std::clamp(rate_, double(options_.floor_kbps), double(options_.ceiling_kbps));
  kbps_ = int(std::lround(rate_));
  return kbps_;
}

}  // namespace rt::media
