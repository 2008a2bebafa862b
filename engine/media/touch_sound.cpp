#include "media/touch_sound.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace rt::media {
namespace {

constexpr double kRate = kTouchSoundRate;

// A band-pass biquad (the audio EQ cookbook's, 0 dB at its centre): shapes white noise into the
// band where a sound's energy lies.
class BandPass {
 public:
  BandPass(double centre_hz, double q) {
    const double w0 = 2.0 * std::numbers::pi * centre_hz / kRate, alpha = std::sin(w0) / (2.0 * q), a0 = 1.0 + alpha;
    b0_ = alpha / a0;
    b2_ = -alpha / a0;
    a1_ = -2.0 * std::cos(w0) / a0;
    a2_ = (1.0 - alpha) / a0;
  }
  double operator()(double x) {
    const double y = b0_ * x + b2_ * x2_ - a1_ * y1_ - a2_ * y2_;
    x2_ = x1_;
    x1_ = x;
    y2_ = y1_;
    y1_ = y;
    return y;
  }

 private:
  double b0_ = 0, b2_ = 0, a1_ = 0, a2_ = 0, x1_ = 0, x2_ = 0, y1_ = 0, y2_ = 0;
};

// Rises linearly over `attack_s`, then decays with time constant `decay_s`.
double burst_envelope(double t, double attack_s, double decay_s) {
  if (t < 0) return 0.0;
  return t < attack_s ? t / attack_s : std::exp(-(t - attack_s) / decay_s);
}

void normalise_peak(std::vector<float>& samples, double peak) {
  float largest = 0.0f;
  for (float s : samples) largest = std::max(largest, std::abs(s));
  if (largest > 0.0f)
    for (float& s : samples) s = float(double(s) * peak / double(largest));
}

std::vector<float> clap() {
  // Three bursts a few milliseconds apart (the palms' air pocket closing unevenly) over the ring
  // of the hands' cavities, a little lower.
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  BandPass air(1800.0, 1.1), ring(1000.0, 3.0);
  std::vector<float> out(size_t(0.15 * kRate));
  constexpr double kBurstAt[] = {0.0, 0.0025, 0.0055}, kBurstLevel[] = {1.0, 0.6, 0.35};
  for (size_t i = 0; i < out.size(); ++i) {
    const double t = double(i) / kRate;
    double envelope = 0.0;
    for (int b = 0; b < 3; ++b) envelope += kBurstLevel[b] * burst_envelope(t - kBurstAt[b], 0.0002, 0.004);
    const double n = noise(random);
    out[i] = float(envelope * air(n) + 0.25 * burst_envelope(t, 0.0005, 0.025) * ring(n));
  }
  normalise_peak(out, 0.7);
  return out;
}

std::vector<float> fist_bump() {
  // Knuckles meeting: a low, damped body with a dull click, nothing bright.
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  BandPass click(500.0, 0.8);
  std::vector<float> out(size_t(0.2 * kRate));
  for (size_t i = 0; i < out.size(); ++i) {
    const double t = double(i) / kRate;
    const double body = std::sin(2.0 * std::numbers::pi * 110.0 * t) * burst_envelope(t, 0.001, 0.035);
    out[i] = float(body + 0.6 * burst_envelope(t, 0.0005, 0.006) * click(noise(random)));
  }
  normalise_peak(out, 0.7);
  return out;
}

std::vector<float> finger_tap() {
  std::mt19937 random(13);
  std::normal_distribution<double> noise(0.0, 1.0);
  BandPass tick(6000.0, 1.5);
  std::vector<float> out(size_t(0.04 * kRate));
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = float(burst_envelope(double(i) / kRate, 0.0001, 0.0025) * tick(noise(random)));
  normalise_peak(out, 0.45);
  return out;
}

}  // namespace

const char* touch_sound_name(TouchSound sound) {
  switch (sound) {
    case TouchSound::Clap: return "clap";
    case TouchSound::FistBump: return "fist bump";
    case TouchSound::FingerTap: return "finger tap";
  }
  return "?";
}

std::vector<float> synthesize_touch_sound(TouchSound sound) {
  switch (sound) {
    case TouchSound::Clap: return clap();
    case TouchSound::FistBump: return fist_bump();
    case TouchSound::FingerTap: return finger_tap();
  }
  return {};
}

StereoPlacement place_between_loudspeakers(const Eigen::Vector3d& source_m, const Eigen::Vector3d& head_m) {
  StereoPlacement placement;
  if (!source_m.allFinite() || !head_m.allFinite()) return placement;
  const double across = source_m.x() - head_m.x(), ahead = head_m.z() - source_m.z();
  const double half_pi = std::numbers::pi / 2.0;
  double azimuth = ahead > 0.0 ? std::atan2(across, ahead) : (across > 0 ? half_pi : across < 0 ? -half_pi : 0.0);
  azimuth = std::clamp(azimuth, -half_pi, half_pi);
  const double pan = (std::sin(azimuth) + 1.0) * std::numbers::pi / 4.0;
  placement.gain_left = float(std::cos(pan));
  placement.gain_right = float(std::sin(pan));
  // The far ear hears it later by the path around the head.
  constexpr double kHeadRadiusM = 0.0875, kSoundSpeedMps = 343.0;
  const double lag_s = kHeadRadiusM / kSoundSpeedMps * (std::abs(azimuth) + std::sin(std::abs(azimuth)));
  const size_t lag = size_t(std::lround(lag_s * kRate));
  (azimuth > 0 ? placement.delay_left_samples : placement.delay_right_samples) = lag;
  placement.azimuth_rad = azimuth;
  return placement;
}

TouchSoundMixer::TouchSoundMixer() {
  for (TouchSound sound : {TouchSound::Clap, TouchSound::FistBump, TouchSound::FingerTap})
    synthesized_[size_t(sound)] = synthesize_touch_sound(sound);
  sounds_.reserve(kMaxSounds);
}

uint64_t TouchSoundMixer::schedule(TouchSound sound, uint64_t onset_sample, const StereoPlacement& placement) {
  if (sounds_.size() >= kMaxSounds) {
    sounds_.erase(sounds_.begin());
    ++dropped_;
  }
  sounds_.push_back({next_id_, sound, onset_sample, placement});
  return next_id_++;
}

bool TouchSoundMixer::cancel(uint64_t id, uint64_t next_sample) {
  const auto it = std::find_if(sounds_.begin(), sounds_.end(), [&](const Playing& p) { return p.id == id; });
  if (it == sounds_.end() || it->onset_sample < next_sample) return false;
  sounds_.erase(it);
  return true;
}

void TouchSoundMixer::mix_into(std::span<float> stereo, uint64_t first_sample) {
  const uint64_t frames = stereo.size() / 2;
  for (const Playing& p : sounds_) {
    const std::vector<float>& samples = synthesized_[size_t(p.sound)];
    const float gains[2] = {p.placement.gain_left, p.placement.gain_right};
    const uint64_t starts[2] = {p.onset_sample + p.placement.delay_left_samples,
                                p.onset_sample + p.placement.delay_right_samples};
    for (int channel = 0; channel < 2; ++channel) {
      const uint64_t begin = std::max(first_sample, starts[channel]);
      const uint64_t end = std::min(first_sample + frames, starts[channel] + samples.size());
      for (uint64_t s = begin; s < end; ++s)
        stereo[size_t(s - first_sample) * 2 + size_t(channel)] += gains[channel] * samples[size_t(s - starts[channel])];
    }
  }
  const uint64_t next = first_sample + frames;
  std::erase_if(sounds_, [&](const Playing& p) {
    const size_t last_delay = std::max(p.placement.delay_left_samples, p.placement.delay_right_samples);
    return p.onset_sample + last_delay + synthesized_[size_t(p.sound)].size() <= next;
  });
  for (float& s : stereo) s = std::clamp(s, -1.0f, 1.0f);
}

}  // namespace rt::media
