#include "audio/simulated_room.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt::audio {

std::string check_echo_path(const EchoPathOptions& o) {
  auto within = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!within(o.delay_ms, 10.0, 500.0))
    return "echo delay " + std::to_string(o.delay_ms) + " ms is outside 10..500 ms (a room, not a hall)";
  if (!within(o.gain_db, -60.0, 0.0)) return "echo gain " + std::to_string(o.gain_db) + " dB is outside -60..0 dB";
  if (o.reverb_taps < 0 || o.reverb_taps > 64) return "echo reverb taps " + std::to_string(o.reverb_taps) + " outside 0..64";
  if (!within(o.reverb_ms, 0.0, 1000.0)) return "echo reverb " + std::to_string(o.reverb_ms) + " ms is outside 0..1000 ms";
  if (!within(o.reverb_db, -80.0, 0.0)) return "echo reverb level " + std::to_string(o.reverb_db) + " dB is outside -80..0 dB";
  return {};
}

std::vector<EchoTap> echo_taps(const EchoPathOptions& o) {
  std::vector<EchoTap> taps;
  taps.reserve(size_t(o.reverb_taps) + 1);
  const auto samples = [](double ms) { return size_t(std::lround(ms * kSampleRate / 1000.0)); };
  const double direct = std::pow(10.0, o.gain_db / 20.0);
  taps.push_back({samples(o.delay_ms), float(direct)});
  for (int i = 1; i <= o.reverb_taps; ++i) {
    const double fraction = double(i) / o.reverb_taps;
    // Spread unevenly, as walls at different distances would: no comb-filter ring.
    const double at = o.delay_ms + o.reverb_ms * std::pow(fraction, 0.8);
    const double level_db = o.gain_db + o.reverb_db * fraction;
    const double sign = (i % 2) ? -1.0 : 1.0;
    taps.push_back({samples(at), float(sign * std::pow(10.0, level_db / 20.0))});
  }
  return taps;
}

class RoomMicrophone final : public AudioInput {
 public:
  explicit RoomMicrophone(SimulatedRoom& room) : room_(room) {}
  bool read(std::span<float> block) override {
    room_.read_into(block);
    return true;
  }
  std::string description() const override {
    return room_.has_echo() ? "simulated user, with the room's echo" : "simulated user";
  }

 private:
  SimulatedRoom& room_;
};

class RoomLoudspeaker final : public AudioOutput {
 public:
  RoomLoudspeaker(SimulatedRoom& room, int channels) : room_(room), channels_(channels) {}
  void write(std::span<const float> block) override {
    if (channels_ == 1) return room_.play(block);
    mono_.resize(block.size() / size_t(channels_));
    for (size_t i = 0; i < mono_.size(); ++i) {
      float sum = 0.0f;
      for (size_t c = 0; c < size_t(channels_); ++c) sum += block[i * size_t(channels_) + c];
      mono_[i] = sum / float(channels_);
    }
    room_.play(mono_);
  }
  int channels() const override { return channels_; }
  std::string description() const override { return channels_ == 2 ? "simulated loudspeakers (stereo)" : "simulated loudspeaker"; }

 private:
  SimulatedRoom& room_;
  int channels_;
  std::vector<float> mono_;
};

SimulatedRoom::SimulatedRoom(std::vector<float> speech, std::optional<EchoPathOptions> echo, size_t record_seconds)
    : speech_(std::move(speech)), recorded_limit_(std::min(record_seconds, kRecordedSeconds) * kSampleRate) {
  if (echo) {
    if (auto error = check_echo_path(*echo); !error.empty()) throw std::invalid_argument(error);
    taps_ = echo_taps(*echo);
    for (const EchoTap& tap : taps_) reach_ = std::max(reach_, tap.delay_samples + 1);
  }
}

std::unique_ptr<AudioInput> SimulatedRoom::microphone() { return std::make_unique<RoomMicrophone>(*this); }
std::unique_ptr<AudioOutput> SimulatedRoom::loudspeaker(int channels) {
  if (channels != 1 && channels != 2) throw std::invalid_argument("a simulated loudspeaker has 1 or 2 channels");
  return std::make_unique<RoomLoudspeaker>(*this, channels);
}

void SimulatedRoom::play(std::span<const float> block) {
  std::lock_guard lock(mutex_);
  const size_t kRecorded = recorded_limit_;
  const size_t keep = std::min(block.size(), kRecorded - std::min(kRecorded, played_.size()));
  played_.reserve(played_.size() + keep);
  played_.insert(played_.end(), block.begin(), block.begin() + ptrdiff_t(keep));
  played_count_ += block.size();
  if (taps_.empty()) return;
  recent_.insert(recent_.end(), block.begin(), block.end());
  while (recent_.size() > reach_ + block.size()) recent_.pop_front();
}

void SimulatedRoom::read_into(std::span<float> block) {
  std::lock_guard lock(mutex_);
  const size_t kRecorded = recorded_limit_;
  last_powers_ = {};
  const uint64_t oldest = played_count_ - recent_.size();
  for (float& out : block) {
    const uint64_t t = read_++;
    const float said = t < speech_.size() ? speech_[t] : 0.0f;
    float echo = 0.0f;
    for (const EchoTap& tap : taps_) {
      if (t < tap.delay_samples) continue;
      const uint64_t s = t - tap.delay_samples;
      if (s >= oldest && s < played_count_) echo += tap.gain * recent_[size_t(s - oldest)];
    }
    last_powers_.speech += double(said) * said;
    last_powers_.echo += double(echo) * echo;
    if (speech_heard_.size() < kRecorded) {
      // Reserved in whole seconds: GCC 12 warns about inserting into an empty vector otherwise.
      if (speech_heard_.size() == speech_heard_.capacity()) {
        speech_heard_.reserve(speech_heard_.size() + kSampleRate);
        echo_heard_.reserve(echo_heard_.size() + kSampleRate);
      }
      speech_heard_.push_back(said);
      echo_heard_.push_back(echo);
    }
    out = std::clamp(said + echo, -1.0f, 1.0f);
  }
}

SimulatedRoom::BlockPowers SimulatedRoom::last_block_powers() const {
  std::lock_guard lock(mutex_);
  return last_powers_;
}

std::vector<float> SimulatedRoom::echo_heard() const {
  std::lock_guard lock(mutex_);
  return echo_heard_;
}
std::vector<float> SimulatedRoom::speech_heard() const {
  std::lock_guard lock(mutex_);
  return speech_heard_;
}
std::vector<float> SimulatedRoom::played() const {
  std::lock_guard lock(mutex_);
  return played_;
}

}  // namespace rt::audio
