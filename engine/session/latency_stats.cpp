#include "session/latency_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace rt::session {

double percentile(std::vector<double> samples, double fraction) {
  if (samples.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(samples.begin(), samples.end());
  const double rank = std::clamp(fraction, 0.0, 1.0) * double(samples.size() - 1);
  return samples[size_t(std::lround(rank))];
}

void LatencyStats::add(double ms) {
  if (!std::isfinite(ms)) return;
  std::lock_guard lock(mutex_);
  samples_.push_back(ms);
}

size_t LatencyStats::count() const {
  std::lock_guard lock(mutex_);
  return samples_.size();
}

double LatencyStats::median() const {
  std::lock_guard lock(mutex_);
  return percentile(samples_, 0.5);
}

double LatencyStats::recent_median(size_t newest) const {
  std::lock_guard lock(mutex_);
  const size_t n = std::min(newest, samples_.size());
  return percentile(std::vector<double>(samples_.end() - std::ptrdiff_t(n), samples_.end()), 0.5);
}

nlohmann::json LatencyStats::to_json() const {
  std::lock_guard lock(mutex_);
  nlohmann::json out = {{"count", samples_.size()}};
  if (samples_.empty()) {
    for (const char* key : {"mean_ms", "median_ms", "p90_ms", "max_ms"}) out[key] = nullptr;
    return out;
  }
  out["mean_ms"] = std::accumulate(samples_.begin(), samples_.end(), 0.0) / double(samples_.size());
  out["median_ms"] = percentile(samples_, 0.5);
  out["p90_ms"] = percentile(samples_, 0.9);
  out["max_ms"] = percentile(samples_, 1.0);
  return out;
}

}  // namespace rt::session
