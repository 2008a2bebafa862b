#pragma once
// Latency samples of one stage (milliseconds), summarised as count, mean, median, 90th
// percentile and maximum. Thread-safe.
#include <nlohmann/json.hpp>

#include <mutex>
#include <vector>

namespace rt::session {

class LatencyStats {
 public:
  void add(double ms);
  size_t count() const;
  double median() const;  // NaN when empty
  // The median of the newest `newest` samples only: what a stage costs now, not over the whole
  // run, at a cost that does not grow with the run. NaN when empty.
  double recent_median(size_t newest) const;
  // {"count", "mean_ms", "median_ms", "p90_ms", "max_ms"}; nulls when empty.
  nlohmann::json to_json() const;

 private:
  mutable std::mutex mutex_;
  std::vector<double> samples_;
};

// The value at `fraction` (0..1) of the sorted samples, nearest rank; NaN when empty.
double percentile(std::vector<double> samples, double fraction);

}  // namespace rt::session
