// The touch's sound (media/touch_sound.h): each kind synthesised finite, bounded and sharp at its
// start, and told apart by where its energy lies; placed between the loudspeakers by the contact
// point's azimuth from the seat, hard cases included; mixed in at the exact sample it is asked
// for, whatever the blocks' sizes, and withdrawn only before it has begun.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "media/marker_claps.h"
#include "media/touch_sound.h"

using namespace rt;
using namespace rt::media;

namespace {

// The frequency below which half of the sound's spectral energy lies, from the energy of its
// first and second differences (a cheap spectral balance: differencing weighs high frequencies).
double brightness_of(const std::vector<float>& samples) {
  double level = 0.0, slope = 0.0;
  for (size_t i = 1; i < samples.size(); ++i) {
    level += double(samples[i]) * samples[i];
    const double d = double(samples[i]) - samples[i - 1];
    slope += d * d;
  }
  // For a sinusoid of frequency f, sum(d^2)/sum(x^2) = (2 sin(pi f / fs))^2.
  return std::asin(std::min(1.0, std::sqrt(slope / level) / 2.0)) * kTouchSoundRate / 3.14159265358979;
}

size_t first_above(const std::vector<float>& samples, float threshold, size_t from = 0, size_t stride = 1) {
  for (size_t i = from; i < samples.size(); i += stride)
    if (std::abs(samples[i]) > threshold) return (i - from) / stride;
  return std::numeric_limits<size_t>::max();
}

}  // namespace

TEST_CASE("touch sound: each kind is finite, bounded, starts at once and sounds its own", "[sound][touch]") {
  double brightness[3] = {};
  for (TouchSound sound : {TouchSound::Clap, TouchSound::FistBump, TouchSound::FingerTap}) {
    INFO(touch_sound_name(sound));
    const std::vector<float> samples = synthesize_touch_sound(sound);
    REQUIRE(samples.size() >= size_t(0.03 * kTouchSoundRate));
    REQUIRE(samples.size() <= size_t(0.25 * kTouchSoundRate));
    float peak = 0.0f;
    size_t peak_at = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
      REQUIRE(std::isfinite(samples[i]));
      if (std::abs(samples[i]) > peak) peak = std::abs(samples[i]), peak_at = i;
    }
    CHECK(peak <= 0.71f);
    CHECK(peak >= 0.3f);
    // Sharp: a tenth of the peak within a millisecond, the peak within a few.
    CHECK(first_above(samples, 0.1f * peak) <= size_t(0.001 * kTouchSoundRate));
    CHECK(peak_at <= size_t(0.008 * kTouchSoundRate));
    // And over: the last 10 ms are 40 dB below the peak.
    float tail = 0.0f;
    for (size_t i = samples.size() - size_t(0.01 * kTouchSoundRate); i < samples.size(); ++i) tail = std::max(tail, std::abs(samples[i]));
    CHECK(tail <= 0.01f * peak);
    brightness[int(sound)] = brightness_of(samples);
    CHECK(synthesize_touch_sound(sound) == samples);  // deterministic
  }
  INFO("brightness Hz: clap " << brightness[0] << ", fist bump " << brightness[1] << ", finger tap " << brightness[2]);
  CHECK(brightness[int(TouchSound::FistBump)] < 0.5 * brightness[int(TouchSound::Clap)]);
  CHECK(brightness[int(TouchSound::FingerTap)] > 1.3 * brightness[int(TouchSound::Clap)]);
}

TEST_CASE("touch sound: placed by the contact point's azimuth from the seat", "[sound][touch]") {
  const Eigen::Vector3d head(0.0, 0.1, 0.6);
  const StereoPlacement centre = place_between_loudspeakers({0.0, 0.0, 0.0}, head);
  CHECK(centre.gain_left == Approx(centre.gain_right));
  CHECK(centre.delay_left_samples == 0);
  CHECK(centre.delay_right_samples == 0);
  CHECK(centre.gain_left * centre.gain_left + centre.gain_right * centre.gain_right == Approx(1.0));

  const StereoPlacement right = place_between_loudspeakers({0.3, 0.0, 0.0}, head);
  CHECK(right.azimuth_rad == Approx(std::atan2(0.3, 0.6)));
  CHECK(right.gain_right > right.gain_left);
  CHECK(right.gain_left * right.gain_left + right.gain_right * right.gain_right == Approx(1.0));
  CHECK(right.delay_right_samples == 0);
  // Woodworth: r/c (theta + sin theta), 0.26 ms at this azimuth.
  const double lag_s = 0.0875 / 343.0 * (right.azimuth_rad + std::sin(right.azimuth_rad));
  CHECK(double(right.delay_left_samples) == Approx(lag_s * kTouchSoundRate).margin(0.5));

  const StereoPlacement left = place_between_loudspeakers({-0.3, 0.0, 0.0}, head);
  CHECK(left.gain_left == Approx(right.gain_right));
  CHECK(left.delay_right_samples == right.delay_left_samples);
  CHECK(left.delay_left_samples == 0);

  // Hard cases: beside or behind the head (the far side of the listener), exactly above it, NaN.
  const StereoPlacement beside = place_between_loudspeakers({1.0, 0.0, 0.6}, head);
  CHECK(beside.azimuth_rad == Approx(3.14159265358979 / 2));
  CHECK(beside.gain_left == Approx(0.0).margin(1e-6));
  CHECK(beside.delay_left_samples <= 32);  // at most the head's width: 0.66 ms
  const StereoPlacement behind = place_between_loudspeakers({-0.5, 0.0, 2.0}, head);
  CHECK(behind.azimuth_rad == Approx(-3.14159265358979 / 2));
  const StereoPlacement above = place_between_loudspeakers({0.0, 1.0, 0.6}, head);
  CHECK(above.gain_left == Approx(above.gain_right));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const StereoPlacement& p : {place_between_loudspeakers({nan, 0.0, 0.0}, head),
                                   place_between_loudspeakers({0.0, 0.0, 0.0}, {0.0, nan, 0.6}),
                                   place_between_loudspeakers({std::numeric_limits<double>::infinity(), 0.0, 0.0}, head)}) {
    CHECK(p.gain_left == Approx(centre.gain_left));
    CHECK(p.gain_right == Approx(centre.gain_right));
    CHECK(p.delay_left_samples + p.delay_right_samples == 0);
  }
}

TEST_CASE("touch sound: mixed in at its sample whatever the blocks, withdrawn only before it starts", "[sound][touch]") {
  TouchSoundMixer mixer;
  const std::vector<float>& clap = mixer.samples_of(TouchSound::Clap);
  const StereoPlacement placement = place_between_loudspeakers({0.25, 0.0, 0.0}, {0.0, 0.0, 0.6});
  const uint64_t onset = 1237;
  mixer.schedule(TouchSound::Clap, onset, placement);
  const uint64_t withdrawn = mixer.schedule(TouchSound::FistBump, 20000, placement);
  CHECK(mixer.cancel(withdrawn, 19999));
  CHECK_FALSE(mixer.cancel(withdrawn, 0));  // gone
  // Blocks of odd sizes over a bed of a constant 0.2 (a voice), interleaved left/right.
  std::vector<float> left, right;
  uint64_t sample = 0;
  for (size_t size : {1u, 479u, 480u, 331u, 2047u, 3u, 480u, 4000u, 10000u}) {
    std::vector<float> block(size * 2, 0.2f);
    mixer.mix_into(block, sample);
    for (size_t i = 0; i < size; ++i) {
      left.push_back(block[2 * i]);
      right.push_back(block[2 * i + 1]);
    }
    sample += size;
  }
  CHECK(mixer.pending() == 0);  // played out and let go
  for (float s : left) REQUIRE(std::isfinite(s));
  for (size_t i = 0; i < left.size(); ++i) {
    const uint64_t s = i;
    const float expect_right = 0.2f + (s >= onset && s < onset + clap.size() ? placement.gain_right * clap[size_t(s - onset)] : 0.0f);
    const uint64_t left_onset = onset + placement.delay_left_samples;
    const float expect_left =
        0.2f + (s >= left_onset && s < left_onset + clap.size() ? placement.gain_left * clap[size_t(s - left_onset)] : 0.0f);
    REQUIRE(right[i] == Approx(std::clamp(expect_right, -1.0f, 1.0f)).margin(1e-6));
    REQUIRE(left[i] == Approx(std::clamp(expect_left, -1.0f, 1.0f)).margin(1e-6));
  }
  CHECK(placement.delay_left_samples > 0);

  // Started: it plays out. Past the bound: the oldest goes.
  TouchSoundMixer busy;
  const uint64_t first = busy.schedule(TouchSound::Clap, 100, {});
  std::vector<float> block(2 * 200, 0.0f);
  busy.mix_into(block, 0);
  CHECK_FALSE(busy.cancel(first, 200));
  for (size_t i = 0; i < TouchSoundMixer::kMaxSounds; ++i) busy.schedule(TouchSound::FingerTap, 1000 + i, {});
  CHECK(busy.pending() == TouchSoundMixer::kMaxSounds);
  CHECK(busy.dropped() == 1);
}

TEST_CASE("marker claps: each at its sample whatever the blocks, nothing elsewhere, clamped", "[sound][marker]") {
  const std::vector<float> clap = synthesize_touch_sound(TouchSound::Clap);
  const std::vector<uint64_t> onsets = {1000, 1000 + clap.size() + 7, 30000};
  const MarkerClaps claps({onsets[2], onsets[0], onsets[1]});  // any order
  CHECK(claps.onsets() == onsets);
  // The microphone's stream in odd blocks, over a quiet hum.
  std::vector<float> stream(40000, 0.01f);
  for (size_t first = 0, size = 1; first < stream.size(); first += size, size = size * 3 % 997 + 1)
    claps.add_into(std::span<float>(stream).subspan(first, std::min(size, stream.size() - first)), first);
  for (size_t n = 0; n < stream.size(); ++n) {
    float expected = 0.01f;
    for (const uint64_t onset : onsets)
      if (n >= onset && n < onset + clap.size()) expected = std::clamp(expected + clap[n - onset], -1.0f, 1.0f);
    REQUIRE(stream[n] == Approx(expected).margin(1e-7));
  }
  // A loud room does not push the sum past full scale.
  std::vector<float> loud(clap.size(), 0.99f);
  claps.add_into(loud, onsets[0]);
  for (const float s : loud) REQUIRE((s <= 1.0f && s >= -1.0f && std::isfinite(s)));
  // No onset: the block is untouched.
  std::vector<float> untouched(480, 0.5f);
  MarkerClaps({}).add_into(untouched, 0);
  CHECK(std::all_of(untouched.begin(), untouched.end(), [](float s) { return s == 0.5f; }));
}
