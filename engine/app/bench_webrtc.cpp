// `remotetouch bench webrtc`: portraits at 30 fps from one WebRTC peer to another in this process
// over loopback (engine/media/webrtc_peer.h; the offer, answer and candidates handed across
// in-process): bitrate per track and in all, the decoded portrait against the sent one (PSNR over
// the user's pixels, depth error, silhouette IoU) and the latency from a portrait handed to the
// sender to its three parts paired at the receiver (colour conversion, encode, RTP, DTLS-SRTP, ICE
// on loopback, jitter buffer, decode), and then the taker's conversion to float images. The portrait is media/synthetic_portrait.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <time.h>

#include "app/bench_command.h"
#include "media/portrait_quality.h"
#include "media/synthetic_portrait.h"
#include "media/webrtc_peer.h"
#include "time/monotonic_clock.h"

namespace rt::app {
namespace {

using namespace rt::media;

double webrtc_percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, size_t(fraction * double(values.size())))];
}

// CPU time of the whole process, all threads (both peers: two encoders, two decoders, the
// conversions): what the link costs, whatever else loads the machine.
double webrtc_process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) / 1e6;
}

// Each peer's signalling, queued from GStreamer's threads and delivered on the bench's.
struct WebRtcBenchSignals {
  struct Said {
    bool to_answerer = false, description = false;
    std::string type, text;
    unsigned mline = 0;
  };
  std::mutex mutex;
  std::vector<Said> queue;
  Signalling from(bool offerer) {
    Signalling s;
    s.on_description = [this, offerer](const std::string& type, const std::string& sdp) {
      std::lock_guard lock(mutex);
      queue.push_back({offerer, true, type, sdp, 0});
    };
    s.on_candidate = [this, offerer](unsigned mline, const std::string& candidate) {
      std::lock_guard lock(mutex);
      queue.push_back({offerer, false, "", candidate, mline});
    };
    return s;
  }
  void deliver(WebRtcPeer& offerer, WebRtcPeer& answerer) {
    std::vector<Said> said;
    {
      std::lock_guard lock(mutex);
      said.swap(queue);
    }
    for (const Said& s : said) {
      WebRtcPeer& to = s.to_answerer ? answerer : offerer;
      if (!s.description) to.add_ice_candidate(s.mline, s.text);
      else if (const std::string error = to.set_remote_description(s.type, s.text); !error.empty())
        throw std::runtime_error("bench webrtc: " + error);
    }
  }
};

}  // namespace

int run_bench_webrtc(const RunOptions& options) {
  const uint32_t width = options.width > 0 ? options.width : 1280, height = options.width > 0 ? options.height : 720;
  constexpr uint32_t warmup = 30, distinct = 12;
  WebRtcPeerOptions a;
  a.name = "bench A";
  a.offerer = true;
  a.width = width;
  a.height = height;
  WebRtcPeerOptions b = a;
  b.name = "bench B";
  b.offerer = false;
  b.max_queued_portraits = 64;
  WebRtcBenchSignals signals;
  WebRtcPeer sender(a, signals.from(true));
  WebRtcPeer receiver(b, signals.from(false));

  // A few distinct portraits made beforehand and played back and forth (smooth motion), so that
  // making them does not take the 2 cores the encoders need.
  std::vector<net::PortraitMessage> portraits;
  for (uint32_t i = 0; i < distinct; ++i) portraits.push_back(synthetic_portrait(width, height, i));
  const auto source_of = [&](uint64_t frame) {
    const uint64_t cycle = 2 * (distinct - 1), at = frame % cycle;
    return size_t(at < distinct ? at : cycle - at);
  };

  sender.send_portrait(portraits[0]);  // the offer needs the tracks' caps
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!(sender.connected() && receiver.connected())) {
    if (std::chrono::steady_clock::now() > deadline)
      throw std::runtime_error("bench webrtc: the loopback call did not connect: " + sender.last_error() + " " +
                               receiver.last_error());
    signals.deliver(sender, receiver);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::printf("webrtc: %ux%u at 30 fps over loopback, %u portraits measured after %u to warm up; colour H.264 %d kbit/s "
              "target, depth+alpha H.264 High 4:4:4 quality %d (ceiling %d kbit/s)\n",
              width, height, options.frames, warmup, a.color_kbps, a.depth_quality, a.depth_kbps);

  std::map<uint64_t, uint64_t> sent_at;  // frame -> when it was handed over
  std::vector<double> latency_ms, take_ms, psnr, depth_error_mm, iou;
  bool finite = true;
  uint64_t measured_received = 0;
  const auto take = [&] {
    for (;;) {
      const uint64_t taking = monotonic_now_us();
      auto r = receiver.take_portrait();
      if (!r) break;
      const uint64_t frame = r->portrait.frame_index;
      if (frame < warmup || !sent_at.count(frame)) continue;
      ++measured_received;
      latency_ms.push_back(double(r->received_us - sent_at[frame]) / 1e3);
      take_ms.push_back(double(monotonic_now_us() - taking) / 1e3);
      // Quality on every third portrait: measuring a 720p portrait takes CPU the encoders need.
      if (frame % 3 == 0) {
        const PortraitQuality q = portrait_quality(portraits[source_of(frame)], r->portrait);
        psnr.push_back(q.psnr_user_db);
        depth_error_mm.push_back(q.depth_median_error_m * 1e3);
        iou.push_back(q.silhouette_iou);
        finite = finite && q.all_finite;
      }
    }
  };
  WebRtcCounters before{};
  uint64_t measure_start = 0;
  double cpu_start = 0.0;
  const uint64_t start = monotonic_now_us();
  const uint32_t total = warmup + options.frames;
  for (uint32_t frame = 0; frame < total; ++frame) {
    while (monotonic_now_us() < start + uint64_t(frame) * 1'000'000 / 30) {
      take();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    if (frame == warmup) {
      before = sender.counters();
      measure_start = monotonic_now_us();
      cpu_start = webrtc_process_cpu_ms();
    }
    net::PortraitMessage& portrait = portraits[source_of(frame)];  // not copied: 18 MB at 720p
    portrait.frame_index = frame;
    sent_at[frame] = monotonic_now_us();
    portrait.capture_timestamp_us = sent_at[frame];
    sender.send_portrait(portrait);
    signals.deliver(sender, receiver);
  }
  const double seconds = double(monotonic_now_us() - measure_start) / 1e6;
  const double cpu_ms_per_portrait = (webrtc_process_cpu_ms() - cpu_start) / double(options.frames);
  const WebRtcCounters after = sender.counters();
  const auto settle = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (measured_received < options.frames && std::chrono::steady_clock::now() < settle) {
    take();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  // Bits per second of the measured frames: RTP packets (headers included) and the frame records;
  // SRTP's tag and the UDP/IP headers add about 40 bytes a packet on top.
  const auto mbit = [&](uint64_t bytes) { return double(bytes) * 8.0 / 1e6 / seconds; };
  const double colour = mbit(after.color_bytes_sent - before.color_bytes_sent);
  const double depth = mbit(after.depth_bytes_sent - before.depth_bytes_sent);
  const double records = mbit(after.channel_bytes_sent - before.channel_bytes_sent);
  const double all = colour + depth + records;
  const WebRtcCounters received = receiver.counters();
  std::printf("  bitrate: colour %.2f Mbit/s, depth+alpha %.2f Mbit/s, frame records %.3f Mbit/s, total %.2f Mbit/s "
              "(RTP packets over %.2f s)\n",
              colour, depth, records, all, seconds);
  std::printf("  quality (%zu portraits): PSNR over the user median %.2f dB (worst %.2f), depth median error median %.2f mm "
              "(worst %.2f), silhouette IoU median %.4f (worst %.4f), %s\n",
              psnr.size(), webrtc_percentile(psnr, 0.5), psnr.empty() ? 0.0 : *std::min_element(psnr.begin(), psnr.end()),
              webrtc_percentile(depth_error_mm, 0.5),
              depth_error_mm.empty() ? 0.0 : *std::max_element(depth_error_mm.begin(), depth_error_mm.end()),
              webrtc_percentile(iou, 0.5), iou.empty() ? 0.0 : *std::min_element(iou.begin(), iou.end()),
              finite ? "all finite" : "NaN or Inf decoded");
  std::printf("  latency, handed to the sender to paired at the receiver: median %.1f ms, p90 %.1f ms, max %.1f ms; "
              "%llu of %u received, %llu frames unpaired; then its conversion to float images %.1f ms (median)\n"
              "  CPU: %.1f ms per portrait, both peers and the measuring together (%.2f cores at 30 fps)\n",
              webrtc_percentile(latency_ms, 0.5), webrtc_percentile(latency_ms, 0.9), webrtc_percentile(latency_ms, 1.0),
              (unsigned long long)measured_received, options.frames, (unsigned long long)received.frames_unpaired,
              webrtc_percentile(take_ms, 0.5), cpu_ms_per_portrait, cpu_ms_per_portrait * 30.0 / 1e3);
  std::printf("  codecs, median ms a picture spends in each: colour encode %.2f, depth+alpha encode %.2f, colour decode "
              "%.2f, depth+alpha decode %.2f; keyframes asked by the receiver %llu\n",
              after.color_encode_ms, after.depth_encode_ms, received.color_decode_ms, received.depth_decode_ms,
              (unsigned long long)received.keyframes_asked);
  nlohmann::json report = {{"width", width},
                           {"height", height},
                           {"portraits", options.frames},
                           {"received", measured_received},
                           {"frames_unpaired", received.frames_unpaired},
                           {"seconds", seconds},
                           {"colour_mbit_s", colour},
                           {"depth_alpha_mbit_s", depth},
                           {"records_mbit_s", records},
                           {"total_mbit_s", all},
                           {"psnr_user_db_median", webrtc_percentile(psnr, 0.5)},
                           {"depth_median_error_mm_median", webrtc_percentile(depth_error_mm, 0.5)},
                           {"silhouette_iou_median", webrtc_percentile(iou, 0.5)},
                           {"all_finite", finite},
                           {"latency_ms_median", webrtc_percentile(latency_ms, 0.5)},
                           {"latency_ms_p90", webrtc_percentile(latency_ms, 0.9)},
                           {"take_ms_median", webrtc_percentile(take_ms, 0.5)},
                           {"cpu_ms_per_portrait", cpu_ms_per_portrait},
                           {"encode_ms_median", {{"colour", after.color_encode_ms}, {"depth_alpha", after.depth_encode_ms}}},
                           {"decode_ms_median", {{"colour", received.color_decode_ms}, {"depth_alpha", received.depth_decode_ms}}},
                           {"keyframes_asked", received.keyframes_asked}};
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_webrtc.json") << report.dump(2) << "\n";
  if (measured_received == 0) throw std::runtime_error("bench webrtc: no portrait came through: " + receiver.last_error());
  return 0;
}

std::unique_ptr<Command> make_bench_webrtc_command() {
  class BenchWebRtc : public BenchCommand {
   public:
    BenchWebRtc()
        : BenchCommand("webrtc",
                       "Portraits at 30 fps between two WebRTC peers over loopback: bitrate per track, PSNR, depth "
                       "error and IoU of the decoded portrait, latency; OUT/bench_webrtc.json",
                       "Portraits measured (after 30 to warm up)", "1280x720", 150) {}
    int run() override { return run_bench_webrtc(options_); }
  };
  return std::make_unique<BenchWebRtc>();
}

}  // namespace rt::app
