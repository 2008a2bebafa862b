#pragma once
// Whether speech arrived whole: the loudness envelope of what was said against what was heard,
// after the delay between them is found. Words lost, cut or smeared lower the correlation; the
// codec's change of the waveform itself hardly moves it.
#include <span>
#include <vector>

namespace rt::media {

struct EnvelopeMatch {
  double correlation = 0.0;  // Pearson, of the 10 ms RMS envelopes, at the best lag
  double lag_ms = 0.0;       // how much later `heard` is than `said`
};

// Searches lags 0..max_lag_s. Empty or silent input gives correlation 0.
EnvelopeMatch envelope_match(std::span<const float> said, std::span<const float> heard, double max_lag_s);

std::vector<double> rms_envelope(std::span<const float> samples, size_t window);

}  // namespace rt::media
