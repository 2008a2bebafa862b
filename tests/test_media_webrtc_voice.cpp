// The voice as the call's RTP audio track (media/webrtc_voice_track.h): a sentence spoken by
// espeak-ng, encoded by the site's own Opus encoder frame by frame in real time, sent by one
// loopback peer and played at the other through the site's jitter buffer and decoder, as the
// site's sound thread plays it. Clean, every frame arrives with its capture time exact; under 2 %
// random loss (GStreamer's netsim on the sender's RTP) the sentence still correlates >= 0.9 with
// what was said, and no dropout (a run of concealed frames) lasts longer than 60 ms.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "audio/audio_device.h"
#include "audio/wav_file.h"
#include "media/opus_voice.h"
#include "media/voice_jitter_buffer.h"
#include "media/voice_quality.h"
#include "media/voice_rtp_time.h"
#include "media/webrtc_voice_track.h"
#include "support/output_dir.h"
#include "time/monotonic_clock.h"
#include "webrtc_loopback_call.h"

using namespace rt;
using namespace rt::media;
using rt::test::LoopbackWebRtcCall;

namespace {

std::vector<float> webrtc_voice_sentence() {
  const auto dir = test::output_dir("test_media_webrtc_voice");
  std::filesystem::create_directories(dir);
  const auto path = (dir / "sentence.wav").string();
  const std::string command =
      "espeak-ng -v en-us -s 150 -w '" + path +
      "' 'Hello from site A. Put your hand on the glass and we will clap together. Can you hear every word I say?'";
  INFO("needs espeak-ng (scripts/packages.txt): " << command);
  REQUIRE(std::system(command.c_str()) == 0);
  return audio::read_wav_file(path, 30.0);
}

struct VoiceCallFigures {
  EnvelopeMatch match;
  JitterCounters jitter;
  size_t frames_sent = 0, frames_received = 0;
  double worst_stamp_error_us = 0;  // received capture time against the sent one
  VoiceTrackCounters sender, receiver;
  RepairCounters repair;
  std::string receiver_error;
};

// One way, offerer to answerer, the sender's RTP through netsim at `loss`; a 20 ms tick sends the
// next frame and plays one, as the site's sound thread does.
VoiceCallFigures voice_over_a_call(double loss, bool retransmit, int jitter_buffer_ms) {
  const std::vector<float> said = webrtc_voice_sentence();
  LoopbackWebRtcCall call(320, 180, nullptr, nullptr, [&](WebRtcPeerOptions& o) {
    o.simulated_loss = loss;
    o.voice_retransmit = retransmit;
    o.voice_jitter_buffer_ms = jitter_buffer_ms;
  });
  REQUIRE(call.connect(320, 180));
  VoiceEncoder encoder;
  VoiceDecoder decoder;
  VoiceJitterBuffer jitter;
  VoiceCallFigures figures;
  std::vector<float> heard;
  const size_t frames = said.size() / kVoiceFrameSamples + 1;
  const auto start = std::chrono::steady_clock::now();
  const uint64_t start_us = monotonic_now_us();
  for (size_t tick = 0; tick < frames + 25; ++tick) {
    if (tick < frames) {
      std::vector<float> frame(kVoiceFrameSamples, 0.0f);
      for (size_t i = 0; i < frame.size() && tick * frame.size() + i < said.size(); ++i) frame[i] = said[tick * frame.size() + i];
      const std::vector<uint8_t> packet = encoder.encode(frame);
      if (call.offerer->send_voice(packet, start_us + tick * 20000, uint32_t(kVoiceFrameSamples))) ++figures.frames_sent;
    }
    for (const ReceivedVoice& received : call.answerer->take_voice()) {
      // One process, one clock: the receiver's own reading stands in for the sender's heartbeat.
      std::optional<net::VoiceMessage> frame = voice_message_of(received, monotonic_now_us());
      REQUIRE(frame);
      ++figures.frames_received;
      const double since_start = double(int64_t(frame->timestamp_us) - int64_t(start_us));
      const double off_a_frame = std::abs(since_start - 20000.0 * std::round(since_start / 20000.0));
      figures.worst_stamp_error_us = std::max(figures.worst_stamp_error_us, off_a_frame);
      jitter.push(std::move(*frame));
    }
    const VoiceJitterBuffer::Playout playout = jitter.pop();
    std::vector<float> out(kVoiceFrameSamples, 0.0f);
    if (playout.slot == VoiceJitterBuffer::Slot::Frame) out = decoder.decode(playout.frame.packet);
    if (playout.slot == VoiceJitterBuffer::Slot::Lost) out = decoder.conceal();
    heard.insert(heard.end(), out.begin(), out.end());
    std::this_thread::sleep_until(start + std::chrono::milliseconds(20 * (tick + 1)));
  }
  figures.match = envelope_match(said, heard, 0.5);
  figures.jitter = jitter.counters();
  figures.sender = call.offerer->counters().voice;
  figures.receiver = call.answerer->counters().voice;
  figures.repair = call.answerer->counters().repair;
  figures.receiver_error = call.answerer->last_error();
  return figures;
}

std::string describe_voice_call(const VoiceCallFigures& f) {
  std::ostringstream s;
  s << "envelope correlation " << f.match.correlation << " at " << f.match.lag_ms << " ms; frames sent " << f.frames_sent
    << ", received " << f.frames_received << ", played " << f.jitter.played << ", concealed " << f.jitter.lost << ", late "
    << f.jitter.late << ", longest dropout " << f.jitter.longest_concealed_run * 20 << " ms; packets lost past repair "
    << f.receiver.packets_lost << "; retransmissions asked " << f.repair.retransmissions_asked << ", arrived "
    << f.repair.retransmissions_arrived << "; worst capture-time error " << f.worst_stamp_error_us << " us";
  if (!f.receiver_error.empty()) s << "; the receiver's last error: " << f.receiver_error;
  return s.str();
}

}  // namespace

TEST_CASE("webrtc voice: RTP time carries the capture time, sequence numbers extend past their wrap", "[webrtc][voice]") {
  // Within a tick both ways, at any uptime, with the reference a few hours either side.
  for (const uint64_t capture : {uint64_t(0), uint64_t(20000), uint64_t(123456789012), uint64_t(3) * 86400 * 1000000 + 17,
                                 uint64_t(40) * 86400 * 1000000 + 999983}) {
    for (const int64_t hours : {0, -3, 5, 11}) {
      const int64_t shift = hours * 3600 * int64_t(1000000);
      const uint64_t reference = uint64_t(std::max<int64_t>(0, int64_t(capture) + shift));
      const uint64_t back = voice_capture_us(voice_rtp_time(capture), reference);
      INFO("capture " << capture << " reference " << reference);
      CHECK(std::abs(double(int64_t(back) - int64_t(capture))) <= 21.0);
    }
  }
  // A reference a whole wrap (24.8 h) away names another time: the 12 hours are a real limit.
  const uint64_t capture = uint64_t(5) * 86400 * 1000000;
  CHECK(std::abs(double(int64_t(voice_capture_us(voice_rtp_time(capture), capture + 90000ull * 1000000)) - int64_t(capture))) > 1e9);

  SequenceExtender extender;
  CHECK(extender.extend(65534) == 65534);
  CHECK(extender.extend(65535) == 65535);
  CHECK(extender.extend(1) == 65537);       // past the wrap, one lost
  CHECK(extender.extend(65535) == 65535);   // a late one stays where it was
  CHECK(extender.extend(0) == 65536);
  CHECK(extender.extend(2) == 65538);

  ReceivedVoice received{7, voice_rtp_time(1000000), {0xF8, 0xFF, 0xFE}};
  const auto frame = voice_message_of(received, 1000000);
  REQUIRE(frame);
  CHECK(frame->frame_samples == 960);
  CHECK(frame->sequence == 7);
  CHECK(frame->timestamp_us == 1000000);
  received.packet = {0xFF};  // a code-3 packet without its frame count: not a frame
  CHECK_FALSE(voice_message_of(received, 1000000));
}

TEST_CASE("webrtc voice: a sentence over a clean call arrives whole, every capture time exact", "[webrtc][voice]") {
  const WebRtcPeerOptions defaults;
  const VoiceCallFigures f = voice_over_a_call(0.0, defaults.voice_retransmit, defaults.voice_jitter_buffer_ms);
  WARN("clean: " << describe_voice_call(f));
  CHECK(f.frames_sent > 200);
  CHECK(f.frames_received == f.frames_sent);
  CHECK(f.jitter.played == f.frames_sent);
  CHECK(f.jitter.longest_concealed_run == 0);  // (the frames after the last one sent are concealed)
  CHECK(f.receiver.packets_lost == 0);
  CHECK(f.worst_stamp_error_us <= 21.0);
  CHECK(f.match.correlation >= 0.9);
}

TEST_CASE("webrtc voice: at 2 % random loss no dropout is longer than 60 ms", "[webrtc][voice]") {
  // As the sites make their calls: the options' defaults.
  const WebRtcPeerOptions defaults;
  const VoiceCallFigures f = voice_over_a_call(0.02, defaults.voice_retransmit, defaults.voice_jitter_buffer_ms);
  WARN("2 % loss: " << describe_voice_call(f));
  CHECK(f.receiver.packets_lost + f.repair.retransmissions_asked > 0);  // the loss was there
  CHECK(f.jitter.longest_concealed_run * 20 <= 60);
  CHECK(f.match.correlation >= 0.9);
}

// The choices docs/sound.md weighs, by name only: `remotetouch_cpu_tests "[.voice_variants]" -s`.
TEST_CASE("webrtc voice: retransmission and the jitter buffer's wait, compared", "[.voice_variants]") {
  struct Variant {
    const char* name;
    bool retransmit;
    int jitter_buffer_ms;
  };
  for (const Variant v : {Variant{"no NACK, 20 ms wait", false, 20}, Variant{"no NACK, 40 ms wait", false, 40},
                          Variant{"no NACK, the call's 200 ms wait", false, 200}, Variant{"NACK, 20 ms wait", true, 20},
                          Variant{"NACK, 40 ms wait", true, 40}, Variant{"NACK, 200 ms wait", true, 200}}) {
    const VoiceCallFigures f = voice_over_a_call(0.02, v.retransmit, v.jitter_buffer_ms);
    WARN(v.name << ": " << describe_voice_call(f));
  }
}
