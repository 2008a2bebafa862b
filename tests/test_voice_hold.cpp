// The far voice held to the far portrait (media/voice_hold.h): its capture-to-play latency comes
// to the target and stays within the dead band, only silence is added or skipped (every spoken
// sample plays, in order), no target plays the voice as it comes, and the hard cases (no target,
// a target it cannot reach, stamps from the future, lost frames, a stalled player) stay bounded.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "media/voice_hold.h"

using namespace rt;
using media::VoiceHold;

namespace {

constexpr size_t kHoldBlock = VoiceHold::kBlockSamples;

// A 20 ms frame: speech (a tone whose samples count up, so that order can be read back) or silence.
std::vector<float> hold_test_frame(bool speech, uint32_t index) {
  std::vector<float> frame(2 * kHoldBlock, 0.0f);
  if (speech)
    for (size_t i = 0; i < frame.size(); ++i) frame[i] = 0.1f + 0.8f * float((index * frame.size() + i) % 1000) / 1000.0f;
  return frame;
}

struct HoldRun {
  std::vector<float> played;
  std::vector<double> latency_ms;  // per block, where the block was speech
};

// Frames captured every 20 ms from t = 1 s, arriving `network_ms` later, played in 10 ms blocks;
// `speech(i)` says which frames are speech.
template <typename Speech>
HoldRun run_hold(VoiceHold& hold, double target_ms, double network_ms, size_t frames, Speech speech) {
  HoldRun run;
  hold.hold_to(target_ms);
  const uint64_t start = 1'000'000;
  std::vector<float> block(kHoldBlock);
  for (size_t tick = 0; tick < 2 * frames; ++tick) {
    const uint64_t play_us = start + uint64_t(network_ms * 1000) + tick * 10'000;
    if (tick % 2 == 0) hold.push(hold_test_frame(speech(tick / 2), uint32_t(tick / 2)), start + (tick / 2) * 20'000);
    hold.next_block(block, play_us);
    for (float s : block) REQUIRE(std::isfinite(s));
    run.played.insert(run.played.end(), block.begin(), block.end());
  }
  return run;
}

}  // namespace

TEST_CASE("voice hold: the latency comes to the portrait's in the pauses, and no word is touched", "[sound]") {
  VoiceHold hold;
  // Talk spurts of 0.4 s with 0.2 s pauses, the first pause at the start.
  auto speech = [](size_t i) { return i % 30 >= 10; };
  const HoldRun run = run_hold(hold, 150.0, 60.0, 300, speech);
  INFO(hold.to_json().dump());
  CHECK(hold.silences_added() >= 7);
  CHECK(hold.silences_added() <= 10);
  CHECK(hold.silences_skipped() == 0);
  CHECK(hold.median_latency_ms() >= 150.0 - VoiceHold::kAddBelowMs);
  CHECK(hold.median_latency_ms() <= 150.0 + VoiceHold::kSkipAboveMs);
  // Every spoken sample, in order, nothing between them within a spurt.
  std::vector<float> spoken_in, spoken_out;
  for (size_t i = 0; i < 300; ++i)
    if (speech(i)) {
      const auto frame = hold_test_frame(true, uint32_t(i));
      spoken_in.insert(spoken_in.end(), frame.begin(), frame.end());
    }
  for (float s : run.played)
    if (s != 0.0f) spoken_out.push_back(s);
  // The last frames may still wait in the hold when the run ends.
  REQUIRE(spoken_out.size() <= spoken_in.size());
  CHECK(spoken_out.size() + 12 * kHoldBlock >= spoken_in.size());
  CHECK(std::equal(spoken_out.begin(), spoken_out.end(), spoken_in.begin()));

  // A later portrait, then an earlier one: it follows both ways, through silences only.
  VoiceHold follows;
  run_hold(follows, 250.0, 40.0, 100, speech);
  const uint64_t added = follows.silences_added();
  CHECK(added >= 18);
  follows.hold_to(150.0);
  std::vector<float> block(kHoldBlock);
  for (size_t tick = 0; tick < 200; ++tick) {
    const uint64_t play_us = 1'000'000 + 40'000 + (200 + tick) * 10'000;
    if (tick % 2 == 0) follows.push(hold_test_frame(false, 0), 1'000'000 + (100 + tick / 2) * 20'000);
    follows.next_block(block, play_us);
  }
  CHECK(follows.silences_skipped() >= 6);
  CHECK(follows.late_dropped() == 0);

  // The burst after a cut link: half a second of speech at once, far behind. It catches up to
  // within the drop limit at once, and from there plays every block.
  VoiceHold burst;
  burst.hold_to(100.0);
  for (uint32_t i = 0; i < 25; ++i) burst.push(hold_test_frame(true, i), 1'000'000 + uint64_t(i) * 20'000);
  const uint64_t now = 1'000'000 + 25 * 20'000 + 100'000;  // the last frame is due now
  burst.next_block(block, now);
  const double kept_latency_ms = (double(now) - 1'000'000.0 - double(burst.late_dropped()) * 10'000.0) / 1000.0;
  CHECK(kept_latency_ms <= 100.0 + VoiceHold::kDropAboveMs);
  CHECK(kept_latency_ms > 100.0 + VoiceHold::kDropAboveMs - 10.0);
  CHECK(burst.late_dropped() > 0);
}

TEST_CASE("voice hold: without a target the voice plays as it comes; the hard cases stay bounded", "[sound]") {
  VoiceHold plain;
  const HoldRun run = run_hold(plain, std::numeric_limits<double>::quiet_NaN(), 30.0, 50, [](size_t) { return false; });
  CHECK(plain.silences_added() == 0);
  CHECK(plain.silences_skipped() == 0);
  CHECK(plain.median_latency_ms() == Approx(30.0).margin(10.0));

  // A target it cannot reach while the far user talks on: it waits for a pause, adds nothing.
  VoiceHold talking;
  run_hold(talking, 300.0, 20.0, 100, [](size_t) { return true; });
  CHECK(talking.silences_added() == 0);
  CHECK(talking.median_latency_ms() == Approx(20.0).margin(10.0));

  // A target beyond what it may hold: it stops at its bound, never grows past it.
  VoiceHold bounded;
  run_hold(bounded, 1e9, 0.0, 200, [](size_t) { return false; });
  CHECK(bounded.buffered_blocks() <= VoiceHold::kMaxBlocks);
  CHECK(bounded.silences_added() >= VoiceHold::kMaxBlocks - 2);

  // Stamps from the future (a clock that jumped), infinite targets, a lost frame's concealment
  // with no stamp, and a player that stalled while frames kept coming.
  VoiceHold odd;
  std::vector<float> block(kHoldBlock);
  odd.hold_to(std::numeric_limits<double>::infinity());
  odd.push(hold_test_frame(false, 0), 9'000'000'000ull);
  odd.next_block(block, 1'000);
  odd.push(hold_test_frame(true, 1), std::nullopt);
  odd.hold_to(-std::numeric_limits<double>::infinity());
  for (int i = 0; i < 5; ++i) odd.next_block(block, 2'000 + uint64_t(i) * 10'000);
  for (int i = 0; i < 200; ++i) odd.push(hold_test_frame(true, uint32_t(i)), 1'000'000 + uint64_t(i) * 20'000);
  CHECK(odd.buffered_blocks() == VoiceHold::kMaxBlocks);
  CHECK(odd.to_json()["overflow_dropped_blocks"].get<uint64_t>() >= 300);
  odd.push(std::vector<float>(100, 0.5f), 5);  // less than a block: nothing to hold
  CHECK(odd.buffered_blocks() == VoiceHold::kMaxBlocks);
  CHECK(std::isfinite(odd.median_latency_ms()));
}
