#include "media/marker_claps.h"

#include <algorithm>

#include "media/touch_sound.h"

namespace rt::media {

MarkerClaps::MarkerClaps(std::vector<uint64_t> onset_samples)
    : onsets_(std::move(onset_samples)), clap_(synthesize_touch_sound(TouchSound::Clap)) {
  std::sort(onsets_.begin(), onsets_.end());
}

void MarkerClaps::add_into(std::span<float> block, uint64_t first_sample) const {
  const uint64_t end_sample = first_sample + block.size();
  // Only the claps that overlap the block: those starting before its end and ending after its start.
  for (auto it = std::lower_bound(onsets_.begin(), onsets_.end(), first_sample > clap_.size() ? first_sample - clap_.size() : 0);
       it != onsets_.end() && *it < end_sample; ++it) {
    const uint64_t from = std::max(*it, first_sample), to = std::min(*it + clap_.size(), end_sample);
    for (uint64_t n = from; n < to; ++n)
      block[n - first_sample] = std::clamp(block[n - first_sample] + clap_[n - *it], -1.0f, 1.0f);
  }
}

}  // namespace rt::media
