#pragma once
// The user's claps of a sound-against-picture marker (the scene effect av_marker), added to what
// the simulated microphone hears at the samples captured when the shirt's flash begins: the
// click that the far site must play as it shows the flash, as a clapperboard's is heard as it is
// seen.
#include <cstdint>
#include <span>
#include <vector>

namespace rt::media {

class MarkerClaps {
 public:
  // `onset_samples`: the microphone's sample index (from its first sample) of each clap.
  explicit MarkerClaps(std::vector<uint64_t> onset_samples);

  // Adds the claps that sound within `block`, whose first sample is `first_sample`.
  void add_into(std::span<float> block, uint64_t first_sample) const;

  const std::vector<uint64_t>& onsets() const { return onsets_; }

 private:
  std::vector<uint64_t> onsets_;
  std::vector<float> clap_;
};

}  // namespace rt::media
