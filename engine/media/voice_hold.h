#pragma once
// The far voice held to the far portrait: decoded voice waits here, 10 ms blocks stamped with
// when the far microphone caught them, and plays so that its capture-to-play latency follows the
// portrait's capture-to-screen latency (lips and words together). The hold grows by playing a
// block of silence and shrinks by skipping one, and only where the voice is silent, so that no
// word is cut or stretched; only a voice far behind (the burst after a cut link) is dropped
// whatever it holds, to catch up at once rather than stay late.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

namespace rt::media {

class VoiceHold {
 public:
  static constexpr size_t kBlockSamples = 480;  // 10 ms at 48 kHz
  static constexpr size_t kMaxBlocks = 50;      // 500 ms: past it the oldest go
  // Around the target: below by more than this, silence is added; above by more, silence is skipped.
  static constexpr double kAddBelowMs = 15.0, kSkipAboveMs = 25.0, kDropAboveMs = 150.0;

  // A decoded frame (whole 10 ms blocks) whose first sample was captured at `captured_us` on the
  // sender's clock (none: concealment for a lost frame, taken to follow the previous one).
  void push(std::span<const float> decoded, std::optional<uint64_t> captured_us);
  // The latency (capture to play, ms) to hold to; NaN: none, play as the frames come.
  void hold_to(double latency_ms) { target_ms_ = latency_ms; }
  // Fills `block` (kBlockSamples) with what plays from `play_us` (this site's clock) on.
  void next_block(std::span<float> block, uint64_t play_us);

  size_t buffered_blocks() const { return blocks_.size(); }
  uint64_t silences_added() const { return added_; }
  uint64_t silences_skipped() const { return skipped_; }
  uint64_t late_dropped() const { return late_dropped_; }
  // Median capture-to-play latency of the blocks played (NaN: none yet), and the figures as JSON.
  double median_latency_ms() const;
  nlohmann::json to_json() const;

 private:
  struct Block {
    std::vector<float> samples;
    uint64_t captured_us = 0;
    bool silent = false;
  };
  std::deque<Block> blocks_;
  uint64_t next_captured_us_ = 0;
  double target_ms_ = std::numeric_limits<double>::quiet_NaN();
  uint64_t added_ = 0, skipped_ = 0, late_dropped_ = 0, overflow_dropped_ = 0;
  std::vector<float> latencies_ms_;  // of the blocks played, the first hour
};

}  // namespace rt::media
