#include "media/voice_quality.h"

#include <cmath>

namespace rt::media {

std::vector<double> rms_envelope(std::span<const float> samples, size_t window) {
  std::vector<double> envelope;
  envelope.reserve(samples.size() / window + 1);
  for (size_t i = 0; i + window <= samples.size(); i += window) {
    double sum = 0.0;
    for (size_t j = 0; j < window; ++j) sum += double(samples[i + j]) * samples[i + j];
    envelope.push_back(std::sqrt(sum / double(window)));
  }
  return envelope;
}

EnvelopeMatch envelope_match(std::span<const float> said, std::span<const float> heard, double max_lag_s) {
  constexpr size_t kWindow = 480;  // 10 ms at 48 kHz
  const auto a = rms_envelope(said, kWindow);
  const auto b = rms_envelope(heard, kWindow);
  EnvelopeMatch best;
  const size_t max_lag = size_t(std::max(0.0, max_lag_s) * 100.0);
  for (size_t lag = 0; lag <= max_lag; ++lag) {
    // Every window of what was said, against the heard window `lag` later (silence past its end).
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    const double n = double(a.size());
    for (size_t i = 0; i < a.size(); ++i) {
      const double x = a[i], y = i + lag < b.size() ? b[i + lag] : 0.0;
      sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
    }
    const double cov = sab - sa * sb / n, va = saa - sa * sa / n, vb = sbb - sb * sb / n;
    if (n < 2 || va <= 0 || vb <= 0) continue;
    const double r = cov / std::sqrt(va * vb);
    if (r > best.correlation) best = {r, double(lag) * 10.0};
  }
  return best;
}

}  // namespace rt::media
