#include "media/voice_hold.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rt::media {
namespace {

constexpr uint64_t kBlockUs = 10'000;
// Below -50 dBFS a block is a pause between words.
constexpr double kSilentPower = 1e-5;
// An hour of blocks: the median needs no more, and a site may run for days.
constexpr size_t kMaxLatencies = 360'000;

}  // namespace

void VoiceHold::push(std::span<const float> decoded, std::optional<uint64_t> captured_us) {
  uint64_t captured = captured_us.value_or(next_captured_us_);
  for (size_t first = 0; first + kBlockSamples <= decoded.size(); first += kBlockSamples) {
    Block block{{decoded.begin() + ptrdiff_t(first), decoded.begin() + ptrdiff_t(first + kBlockSamples)}, captured, false};
    double power = 0.0;
    for (float s : block.samples) power += double(s) * s;
    block.silent = power / double(kBlockSamples) < kSilentPower;
    if (blocks_.size() >= kMaxBlocks) {
      blocks_.pop_front();
      ++overflow_dropped_;
    }
    blocks_.push_back(std::move(block));
    captured += kBlockUs;
  }
  next_captured_us_ = captured;
}

void VoiceHold::next_block(std::span<float> out, uint64_t play_us) {
  std::fill(out.begin(), out.end(), 0.0f);
  if (blocks_.empty()) return;
  auto latency_ms = [&](const Block& block) { return (double(play_us) - double(block.captured_us)) / 1000.0; };
  while (std::isfinite(target_ms_) && blocks_.size() >= 2 && latency_ms(blocks_.front()) > target_ms_ + kDropAboveMs) {
    blocks_.pop_front();
    ++late_dropped_;
  }
  if (std::isfinite(target_ms_) && blocks_.front().silent) {
    if (latency_ms(blocks_.front()) < target_ms_ - kAddBelowMs && blocks_.size() < kMaxBlocks) {
      ++added_;  // the silence already in `out`: everything after it plays 10 ms later
      return;
    }
    if (latency_ms(blocks_.front()) > target_ms_ + kSkipAboveMs && blocks_.size() >= 2) {
      blocks_.pop_front();
      ++skipped_;
    }
  }
  const Block& block = blocks_.front();
  std::copy(block.samples.begin(), block.samples.end(), out.begin());
  if (latencies_ms_.size() < kMaxLatencies) latencies_ms_.push_back(float(latency_ms(block)));
  blocks_.pop_front();
}

double VoiceHold::median_latency_ms() const {
  if (latencies_ms_.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<float> sorted = latencies_ms_;
  std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(sorted.size() / 2), sorted.end());
  return sorted[sorted.size() / 2];
}

nlohmann::json VoiceHold::to_json() const {
  const double median = median_latency_ms();
  return {{"capture_to_play_median_ms", std::isfinite(median) ? nlohmann::json(median) : nlohmann::json()},
          {"held_to_ms", std::isfinite(target_ms_) ? nlohmann::json(target_ms_) : nlohmann::json()},
          {"silences_added", added_},
          {"silences_skipped", skipped_},
          {"late_dropped_blocks", late_dropped_},
          {"overflow_dropped_blocks", overflow_dropped_}};
}

}  // namespace rt::media
