#include "site/site_sound.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <stdexcept>

#include "audio/audio_spec.h"
#include "audio/simulated_room.h"
#include "audio/wav_file.h"
#include "media/echo_canceller.h"
#include "media/opus_voice.h"
#include "media/voice_jitter_buffer.h"
#include "time/monotonic_clock.h"

namespace rt::site {
namespace {

constexpr size_t kBlock = audio::kBlockSamples;
constexpr size_t kFrame = media::kVoiceFrameSamples;
// Behind by more than this, the loop gives up the lost time instead of rushing to make it up.
constexpr uint64_t kMaxLagUs = 200'000;

double power_of(std::span<const float> samples) {
  double sum = 0.0;
  for (float s : samples) sum += double(s) * s;
  return sum;
}

// A single-quoted shell word: the sentence and the path go to espeak-ng as they are.
std::string shell_word(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string simulated_sentence(Site site) {
  return site == Site::A ? "Hello from site A. Can you hear me? Put your hand on the glass and we will clap."
                         : "Hi, this is site B. I hear you well. Ready when you are, let us clap now.";
}

double simulated_sentence_start_s(Site site) { return site == Site::A ? 0.5 : 6.0; }

std::vector<float> speak_with_espeak(const std::string& text, const std::filesystem::path& folder) {
  const std::filesystem::path path = folder / "sentence.wav";
  const std::string command = "espeak-ng -v en-us -s 150 -w " + shell_word(path.string()) + " " + shell_word(text) + " 2>&1";
  if (std::system(command.c_str()) != 0 || !std::filesystem::exists(path))
    throw std::runtime_error("the simulated user's sentence needs espeak-ng: apt-get install espeak-ng (scripts/packages.txt)");
  std::vector<float> speech = audio::read_wav_file(path.string(), 30.0);
  std::filesystem::remove(path);
  return speech;
}

SiteSound::SiteSound(const SoundOptions& options, Site site, const sim::Effects& effects, const std::filesystem::path& out,
                     net::Transport& transport, std::function<void(const std::string&)> log)
    : options_(options), transport_(transport), log_(std::move(log)) {
  const audio::AudioSpec in_spec = audio::parse_audio_spec(options.audio_in, "--audio-in");
  const audio::AudioSpec out_spec = audio::parse_audio_spec(options.audio_out, "--audio-out");
  const bool simulated_in = in_spec.kind == audio::AudioSpec::Kind::Simulated;
  const bool simulated_out = out_spec.kind == audio::AudioSpec::Kind::Simulated;
  std::string in_description, out_description;
  if (simulated_in || simulated_out) {
    std::vector<float> speech;
    // A marker scene's users clap instead of speaking, so that the clap stands alone.
    if (simulated_in && !effects.av_marker) {
      try {
        const std::vector<float> sentence = speak_with_espeak(simulated_sentence(site), out);
        speech_delay_samples_ = size_t(simulated_sentence_start_s(site) * audio::kSampleRate);
        speech.reserve(speech_delay_samples_ + sentence.size());
        speech.assign(speech_delay_samples_, 0.0f);
        speech.insert(speech.end(), sentence.begin(), sentence.end());
      } catch (const std::exception& error) {
        log_(std::string("the simulated user stays silent: ") + error.what());
      }
    }
    // The echo is the room's own loudspeaker heard by its own microphone: both must be the room's.
    std::optional<audio::EchoPathOptions> echo;
    if (effects.room_echo && simulated_in && simulated_out)
      echo = audio::EchoPathOptions{.delay_ms = effects.room_echo->delay_ms,
                                    .gain_db = effects.room_echo->gain_db,
                                    .reverb_ms = effects.room_echo->reverb_ms,
                                    .reverb_db = effects.room_echo->reverb_db};
    // Nothing recorded: a site may run for hours, and its figures are summed as it goes.
    room_ = std::make_unique<audio::SimulatedRoom>(std::move(speech), echo, 0);
  }
  if (simulated_in) {
    in_ = room_->microphone();
    in_description = in_->description();
  } else {
    audio::OpenedInput opened = audio::open_audio_input(in_spec);
    in_ = std::move(opened.device);
    in_description = opened.description;
  }
  if (simulated_out) {
    out_ = room_->loudspeaker(audio::kLoudspeakerChannels);
    out_description = out_->description();
    heard_path_ = out / "audio.wav";
    // The file's first sample played when its block was due, not when the thread woke to write it.
    heard_file_ = std::make_unique<audio::WavFileOutput>(heard_path_.string(), [this] { return block_play_us_; },
                                                         audio::kLoudspeakerChannels);
  } else {
    audio::OpenedOutput opened = audio::open_audio_output(out_spec, {}, audio::kLoudspeakerChannels);
    out_ = std::move(opened.device);
    out_description = opened.description;
  }
  description_ = "in: " + in_description + "; out: " + out_description;
  if (in_) encoder_ = std::make_unique<media::VoiceEncoder>(media::VoiceEncoderOptions{.bitrate_bps = options.voice_bitrate_bps});
  if (out_) {
    decoder_ = std::make_unique<media::VoiceDecoder>();
    jitter_ = std::make_unique<media::VoiceJitterBuffer>();
  }
  // Cancelling needs both halves: what was played, and the microphone that heard it; and an echo
  // to cancel: a real room has one, a simulated room only when the scene asks for it (otherwise
  // the canceller would cost a tenth of a core for nothing), a file none.
  const bool live_room = in_spec.kind == audio::AudioSpec::Kind::Live && out_spec.kind == audio::AudioSpec::Kind::Live;
  if (in_ && out_ && (live_room || (room_ && room_->has_echo())))
    canceller_ = std::make_unique<media::EchoCanceller>(
        media::EchoCancellerOptions{.noise_suppression = options.noise_suppression, .gain_control = options.gain_control});
  capture_frame_.reserve(kFrame);
  touch_sounds_.reserve(64);
}

SiteSound::~SiteSound() {
  try {
    stop();
  } catch (const std::exception& error) {
    log_(std::string("sound: ") + error.what());
  }
}

void SiteSound::start(const std::vector<uint64_t>& marker_claps_us) {
  if (started_ || (!in_ && !out_)) return;
  started_ = true;
  start_us_ = monotonic_now_us();
  if (room_ && in_ && !marker_claps_us.empty()) {
    std::vector<uint64_t> samples;
    for (const uint64_t at_us : marker_claps_us)
      samples.push_back(at_us > start_us_ ? (at_us - start_us_) * uint64_t(audio::kSampleRate) / 1'000'000 : 0);
    marker_claps_ = std::make_unique<media::MarkerClaps>(std::move(samples));
    marker_claps_us_ = marker_claps_us;
  }
  thread_ = std::thread([this] { loop(); });
}

void SiteSound::stop() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
  if (heard_file_) heard_file_->finish();
  if (out_) out_->finish();
}

namespace {
// CPU time this thread has run, in ms: what its work costs, whatever else shares the cores.
double thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return double(now.tv_sec) * 1000.0 + double(now.tv_nsec) / 1e6;
}
}  // namespace

void SiteSound::loop() {
  uint64_t base_us = start_us_, block = 0;
  while (!stopping_) {
    const uint64_t deadline = base_us + audio::samples_to_us((block + 1) * kBlock);
    const uint64_t now = monotonic_now_us();
    if (now + 500 < deadline) {
      std::this_thread::sleep_for(std::chrono::microseconds(deadline - now));
    } else if (now > deadline + kMaxLagUs) {
      ++late_ticks_;
      base_us = now - audio::samples_to_us((block + 1) * kBlock);
    }
    const uint64_t began = monotonic_now_us();
    const double cpu_began = thread_cpu_ms();
    try {
      // The block plays from its deadline on: the moment it is handed to the loudspeaker.
      tick(ticks_, base_us + audio::samples_to_us((block + 1) * kBlock));
    } catch (const std::exception& error) {
      log_(std::string("sound stopped: ") + error.what());
      return;
    }
    loop_ms_ += double(monotonic_now_us() - began) / 1000.0;
    cpu_ms_ += thread_cpu_ms() - cpu_began;
    ++ticks_;
    ++block;
  }
}

void SiteSound::receive(net::VoiceMessage frame) {
  // Five seconds of 20 ms frames: a sound thread that stalled longer has lost them anyway.
  constexpr size_t kMaxReceivedFrames = 250;
  std::lock_guard lock(received_mutex_);
  if (received_.size() >= kMaxReceivedFrames) {
    received_.pop_front();
    ++received_dropped_;
  }
  received_.push_back(std::move(frame));
}

uint64_t SiteSound::play_touch_sound(media::TouchSound sound, uint64_t onset_us, const media::StereoPlacement& placement) {
  if (!out_) return 0;
  // A touch detector gone wrong cannot pile requests up faster than the mixer drops them.
  constexpr size_t kMaxWaitingRequests = media::TouchSoundMixer::kMaxSounds;
  std::lock_guard lock(received_mutex_);
  if (touch_requests_.size() >= kMaxWaitingRequests) touch_requests_.erase(touch_requests_.begin());
  touch_requests_.push_back({next_touch_id_, sound, onset_us, placement});
  return next_touch_id_++;
}

void SiteSound::cancel_touch_sound(uint64_t id) {
  if (id == 0) return;
  std::lock_guard lock(received_mutex_);
  if (std::erase_if(touch_requests_, [&](const TouchSoundRequest& r) { return r.id == id; }) > 0) return;
  if (touch_cancels_.size() < media::TouchSoundMixer::kMaxSounds) touch_cancels_.push_back(id);
}

void SiteSound::take_touch_sound_requests(uint64_t block_index, uint64_t play_us) {
  std::vector<TouchSoundRequest> requests;
  std::vector<uint64_t> cancels;
  {
    std::lock_guard lock(received_mutex_);
    requests.swap(touch_requests_);
    cancels.swap(touch_cancels_);
  }
  const uint64_t block_sample = block_index * kBlock;
  for (const uint64_t id : cancels)
    for (TouchSoundPlayed& played : touch_sounds_)
      if (played.request.id == id && !played.cancelled)
        played.cancelled = touch_mixer_.cancel(played.mixer_id, block_sample);
  for (const TouchSoundRequest& request : requests) {
    // Sample-exact where the onset is still ahead; one already past starts now.
    const uint64_t ahead_us = request.onset_us > play_us ? request.onset_us - play_us : 0;
    const uint64_t onset_sample = block_sample + (ahead_us * uint64_t(audio::kSampleRate) + 500'000) / 1'000'000;
    TouchSoundPlayed played{request, touch_mixer_.schedule(request.sound, onset_sample, request.placement), onset_sample,
                            play_us + audio::samples_to_us(onset_sample - block_sample), false};
    constexpr size_t kKeptTouchSounds = 64;
    if (touch_sounds_.size() < kKeptTouchSounds) touch_sounds_.push_back(played);
  }
}

void SiteSound::tick(uint64_t block_index, uint64_t play_us) {
  block_play_us_ = play_us;
  // The far voice: every voice frame that came, into the jitter buffer; a frame every other tick.
  std::deque<net::VoiceMessage> frames;
  {
    std::lock_guard lock(received_mutex_);
    frames.swap(received_);
  }
  for (net::VoiceMessage& frame : frames) {
    ++voice_frames_in_;
    if (jitter_ && frame.frame_samples == kFrame) jitter_->push(std::move(frame));
  }
  std::vector<float> played(kBlock, 0.0f);
  if (out_) {
    if (block_index % 2 == 0) {
      auto take_frame = [&] {
        const media::VoiceJitterBuffer::Playout playout = jitter_->pop();
        if (playout.slot == media::VoiceJitterBuffer::Slot::Frame)
          voice_hold_.push(decoder_->decode(playout.frame.packet), playout.frame.timestamp_us);
        else if (playout.slot == media::VoiceJitterBuffer::Slot::Lost)
          voice_hold_.push(decoder_->conceal(), std::nullopt);
      };
      take_frame();
      // A backlog (the burst after a cut link) goes to the hold at once, which drops what is far
      // behind: taken a frame per 20 ms, it would keep the voice late for the rest of the call.
      constexpr size_t kBacklogFrames = 6;
      while (jitter_->buffered() > kBacklogFrames) take_frame();
    }
    voice_hold_.hold_to(hold_to_ms_.load());
    voice_hold_.next_block(played, play_us);
    // The voice from both loudspeakers, a touch's sound from where it happened; the microphone
    // (and so the echo canceller's probe) hears their sum.
    take_touch_sound_requests(block_index, play_us);
    speakers_.resize(kBlock * 2);
    for (size_t i = 0; i < kBlock; ++i) speakers_[2 * i] = speakers_[2 * i + 1] = played[i];
    touch_mixer_.mix_into(speakers_, block_index * kBlock);
    for (size_t i = 0; i < kBlock; ++i) played[i] = 0.5f * (speakers_[2 * i] + speakers_[2 * i + 1]);
    out_->write(speakers_);
    if (heard_file_) heard_file_->write(speakers_);
    if (canceller_) canceller_->played(played);
  }
  if (!in_) return;
  std::vector<float> heard(kBlock);
  in_->read(heard);
  if (marker_claps_) marker_claps_->add_into(heard, block_index * kBlock);
  const std::vector<float> cleaned = canceller_ ? canceller_->captured(heard) : heard;
  if (canceller_ && room_ && block_index * kBlock >= 2 * size_t(audio::kSampleRate)) {
    // Echo at least -50 dBFS and the near user silent: the blocks the figure is about.
    const audio::SimulatedRoom::BlockPowers parts = room_->last_block_powers();
    if (parts.speech == 0.0 && parts.echo >= double(kBlock) * 1e-5) {
      erle_in_ += power_of(heard);
      erle_out_ += power_of(cleaned);
      ++erle_blocks_;
    }
  }
  capture_frame_.insert(capture_frame_.end(), cleaned.begin(), cleaned.end());
  if (capture_frame_.size() < kFrame) return;
  const uint64_t began = monotonic_now_us();
  net::VoiceMessage message;
  message.timestamp_us = start_us_ + audio::samples_to_us((block_index + 1) * kBlock - kFrame);
  message.sequence = sequence_++;
  message.frame_samples = uint16_t(kFrame);
  message.packet = encoder_->encode(capture_frame_);
  encode_ms_ += double(monotonic_now_us() - began) / 1000.0;
  capture_frame_.clear();
  voice_bytes_out_ += message.packet.size();
  ++voice_frames_out_;
  transport_.send(message);
}

uint64_t SiteSound::heard_start_us() const { return heard_file_ ? heard_file_->start_us() : 0; }

nlohmann::json SiteSound::metrics() const {
  nlohmann::json m;
  m["devices"] = description_;
  m["ticks"] = ticks_;
  if (marker_claps_) m["marker_claps_us"] = marker_claps_us_;
  m["late_ticks"] = late_ticks_;
  const double seconds = double(ticks_) * double(kBlock) / audio::kSampleRate;
  m["seconds"] = seconds;
  // The ticks' CPU time (the canceller runs in this thread too), and their wall time: on a loaded
  // machine the second also counts the time the thread waited for a core, which is how close
  // the ticks come to their deadlines, not what they cost.
  m["cpu_percent_of_a_core"] = seconds > 0 ? cpu_ms_ / (seconds * 1000.0) * 100.0 : 0.0;
  m["busy_percent_of_the_wall"] = seconds > 0 ? loop_ms_ / (seconds * 1000.0) * 100.0 : 0.0;
  nlohmann::json voice;
  voice["frames_out"] = voice_frames_out_;
  voice["frames_in"] = voice_frames_in_;
  voice["frames_dropped_before_the_sound_thread"] = received_dropped_;
  // The Opus payload alone; each record adds its header, nonce and tag on the wire.
  voice["bitrate_kbps"] = voice_frames_out_ ? double(voice_bytes_out_) * 8.0 / (double(voice_frames_out_) * 0.020) / 1000.0 : 0.0;
  voice["encode_ms_per_frame"] = voice_frames_out_ ? encode_ms_ / double(voice_frames_out_) : 0.0;
  if (jitter_) {
    const media::JitterCounters& c = jitter_->counters();
    voice["jitter"] = {{"played", c.played}, {"lost", c.lost},         {"late", c.late},
                       {"duplicate", c.duplicate}, {"overflow_dropped", c.overflow_dropped}, {"rebuffers", c.rebuffers},
                       {"longest_dropout_ms", audio::samples_to_us(c.longest_concealed_run * kFrame) / 1000.0}};
  }
  if (decoder_) voice["undecodable"] = decoder_->undecodable();
  if (out_) voice["held_to_the_portrait"] = voice_hold_.to_json();
  m["voice"] = voice;
  if (out_) {
    nlohmann::json sounds = nlohmann::json::array();
    for (const TouchSoundPlayed& played : touch_sounds_)
      sounds.push_back({{"sound", media::touch_sound_name(played.request.sound)},
                        {"asked_onset_us", played.request.onset_us},
                        {"onset_us", played.played_us},
                        {"onset_sample", played.onset_sample},
                        {"late_ms", double(int64_t(played.played_us) - int64_t(played.request.onset_us)) / 1000.0},
                        {"cancelled", played.cancelled},
                        {"azimuth_deg", played.request.placement.azimuth_rad * 180.0 / 3.14159265358979},
                        {"gain_left", played.request.placement.gain_left},
                        {"gain_right", played.request.placement.gain_right}});
    m["touch_sounds"] = {{"sounds", sounds},
                         {"dropped", touch_mixer_.dropped()},
                         {"note", "onset_us: when the sound's first sample plays, on the site's monotonic clock; "
                                  "onset_sample: that sample in audio.wav (the loudspeakers' stream)"}};
  }
  if (heard_file_)
    m["audio_wav"] = {{"path", heard_path_.filename().string()},
                      {"start_us", heard_file_->start_us()},
                      {"samples", heard_file_->samples_written()},
                      {"note", "what this site's loudspeaker played; start_us: its first sample, on the site's monotonic clock"}};
  // The echo canceller's enhancement where the microphone heard the far voice's echo alone (this
  // site's user silent), after its first two seconds.
  if (room_ && room_->has_echo() && canceller_) {
    m["echo"] = {{"erle_db_after_2s", erle_blocks_ ? nlohmann::json(10.0 * std::log10(erle_in_ / std::max(erle_out_, erle_in_ * 1e-10 + 1e-20)))
                                                   : nlohmann::json()},
                 {"echo_only_seconds", double(erle_blocks_ * kBlock) / audio::kSampleRate},
                 {"noise_suppression", options_.noise_suppression},
                 {"gain_control", options_.gain_control}};
  }
  return m;
}

}  // namespace rt::site
