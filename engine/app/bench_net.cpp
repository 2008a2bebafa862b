// `remotetouch bench net`: portraits at 30 fps from one session to another over loopback, through
// the real path (JPEG + lossless planes, handshake, sealed records, Asio): bytes per second on the
// wire, bytes per message, and per-message encode and decode milliseconds. The portrait is
// synthetic but shaped like the real one: a person-sized blob with straight-alpha edges, smooth
// color with some texture, depth of a rounded body with 1 mm sensor noise, nothing around it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <time.h>
#include <thread>

#include "app/bench_command.h"
#include "net/image_codec.h"
#include "net/session.h"
#include "time/monotonic_clock.h"

namespace rt::app {
namespace {

using namespace rt::net;

PortraitMessage bench_portrait(uint32_t width, uint32_t height, uint64_t frame) {
  std::mt19937 random(uint32_t(frame) + 1);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  PortraitMessage p;
  p.frame_index = frame;
  p.capture_timestamp_us = monotonic_now_us();
  p.width = width;
  p.height = height;
  p.fx = p.fy = 0.9 * width;
  p.cx = width / 2.0;
  p.cy = height / 2.0 - 0.1 * height;
  p.color = HostImage(width, height, PixelFormat::RGBA32F);
  p.depth = HostImage(width, height, PixelFormat::R32F);
  const float sway = 0.02f * std::sin(float(frame) * 0.2f);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const float u = (float(x) / float(width) - 0.5f - sway) * float(width) / float(height), v = float(y) / float(height) - 0.55f;
      // Head and shoulders: an ellipse over a wider one; soft 2-pixel edge.
      const float head = std::hypot(u / 0.13f, (v + 0.2f) / 0.17f), body = std::hypot(u / 0.32f, (v - 0.35f) / 0.4f);
      const float r = std::min(head, body);
      const float edge = 2.0f / float(height) / 0.15f;
      const float alpha = std::clamp((1.0f - r) / edge, 0.0f, 1.0f);
      p.color.at(x, y, 0) = std::clamp(0.55f + 0.2f * v + 0.03f * std::sin(40.0f * u) + 0.01f * noise(random), 0.0f, 1.0f);
      p.color.at(x, y, 1) = std::clamp(0.42f + 0.1f * u + 0.01f * noise(random), 0.0f, 1.0f);
      p.color.at(x, y, 2) = std::clamp(0.35f + 0.05f * std::cos(30.0f * v) + 0.01f * noise(random), 0.0f, 1.0f);
      p.color.at(x, y, 3) = alpha;
      if (alpha == 0.0f) {
        for (uint32_t c = 0; c < 3; ++c) p.color.at(x, y, c) = 0.0f;
        continue;
      }
      p.depth.at(x, y) = 0.7f + 0.08f * r * r + 0.001f * noise(random);
    }
  return p;
}

// CPU time of the whole process, all threads: robust against other load on the machine, unlike
// wall time.
double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) / 1e6;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

}  // namespace

int run_bench_net(const RunOptions& options) {
  std::vector<std::pair<uint32_t, uint32_t>> sizes = {{640, 360}, {1280, 720}};
  if (options.width > 0) sizes = {{options.width, options.height}};
  const SessionKey key = random_session_key();
  SessionOptions listen;
  listen.role = Role::Listener;
  listen.key = key;
  listen.name = "bench B";
  Session receiver(listen);
  receiver.start();
  SessionOptions connect = listen;
  connect.role = Role::Connector;
  connect.port = receiver.local_port();
  connect.name = "bench A";
  Session sender(connect);
  sender.start();
  if (!sender.wait_connected(std::chrono::seconds(5))) throw std::runtime_error("bench net: the loopback session did not connect");

  nlohmann::json report;
  const EncodeOptions encode;
  std::printf("net: %u portraits per size at 30 fps over loopback, JPEG quality %d, PNG level %d\n", options.frames,
              encode.jpeg_quality, encode.png_compression);
  for (auto [width, height] : sizes) {
    // Encode and decode timed on a few distinct portraits first; the timed 30 fps run then sends
    // those bytes, so its rate is the wire's, not this machine's encoder's.
    std::vector<double> encode_ms, decode_ms, encode_cpu_ms, decode_cpu_ms, message_bytes;
    std::vector<std::vector<uint8_t>> encoded;
    for (uint32_t frame = 0; frame < std::min(options.frames, 6u); ++frame) {
      const PortraitMessage portrait = bench_portrait(width, height, frame);
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = process_cpu_ms();
      encoded.push_back(encode_message(portrait, encode));
      const auto t1 = std::chrono::steady_clock::now();
      const double c1 = process_cpu_ms();
      if (!decode_message(encoded.back()).ok()) throw std::runtime_error("bench net: a portrait does not decode");
      const auto t2 = std::chrono::steady_clock::now();
      const double c2 = process_cpu_ms();
      encode_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      decode_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
      encode_cpu_ms.push_back(c1 - c0);
      decode_cpu_ms.push_back(c2 - c1);
      message_bytes.push_back(double(encoded.back().size()));
    }
    const NetCounters before = sender.counters();
    const uint64_t start = monotonic_now_us();
    for (uint32_t frame = 0; frame < options.frames; ++frame) {
      const uint64_t due = start + uint64_t(frame) * 1'000'000 / 30;
      while (monotonic_now_us() < due) std::this_thread::sleep_for(std::chrono::microseconds(200));
      sender.send_encoded(MessageType::Portrait, encoded[frame % encoded.size()]);
      (void)receiver.take_portrait();  // the receiver decodes each one on its network thread
    }
    const size_t portrait_index = size_t(message_type_index(MessageType::Portrait));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (sender.counters().messages_out[portrait_index] + sender.counters().stale_dropped_out[portrait_index] <
               before.messages_out[portrait_index] + before.stale_dropped_out[portrait_index] + options.frames &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const double seconds = double(monotonic_now_us() - start) / 1e6;
    const NetCounters after = sender.counters();
    const double wire_bytes = double(after.bytes_out - before.bytes_out);
    const uint64_t sent = after.messages_out[portrait_index] - before.messages_out[portrait_index];
    const uint64_t stale = after.stale_dropped_out[portrait_index] - before.stale_dropped_out[portrait_index];
    const double bytes_per_second = wire_bytes / seconds;
    // N portraits sent from the first one's send to the last one's are N - 1 intervals.
    const double portraits_per_second = sent > 1 ? double(sent - 1) / seconds : 0.0;
    // What the stream costs at the full 30 fps, whether or not this machine encoded that fast.
    const double record_bytes = double(sealed_size(size_t(median(message_bytes))));
    const double nominal = record_bytes * 30.0;
    const PortraitMessage sample = bench_portrait(width, height, 0);
    const double jpeg = double(encode_color_jpeg(sample.color, encode.jpeg_quality).size());
    const double alpha = double(encode_float_plane_png(sample.color, 3, encode.png_compression).size());
    const double depth = double(encode_float_plane_png(sample.depth, 0, encode.png_compression).size());
    std::printf("  %ux%u: %.0f B per portrait in its records (color JPEG %.0f, alpha %.0f, depth %.0f); at 30 fps %.2f MB/s = %.1f Mbit/s\n"
                "      measured on the wire: %.2f MB/s over %.2f s (%.1f portraits/s sent, %llu stale); "
                "encode %.1f ms (CPU %.1f ms), decode %.1f ms (CPU %.1f ms), median\n",
                width, height, record_bytes, jpeg, alpha, depth, nominal / 1e6, nominal * 8 / 1e6, bytes_per_second / 1e6,
                seconds, portraits_per_second, (unsigned long long)stale, median(encode_ms), median(encode_cpu_ms),
                median(decode_ms), median(decode_cpu_ms));
    report[std::to_string(width) + "x" + std::to_string(height)] = {
        {"portraits", options.frames},
        {"sent", sent},
        {"stale_dropped", stale},
        {"record_bytes_median", record_bytes},
        {"color_jpeg_bytes", jpeg},
        {"alpha_png_bytes", alpha},
        {"depth_png_bytes", depth},
        {"bytes_per_second_at_30fps", nominal},
        {"wire_bytes", wire_bytes},
        {"seconds", seconds},
        {"portraits_per_second_sent", portraits_per_second},
        {"wire_bytes_per_second_measured", bytes_per_second},
        {"encode_ms_median", median(encode_ms)},
        {"decode_ms_median", median(decode_ms)},
        {"encode_cpu_ms_median", median(encode_cpu_ms)},
        {"decode_cpu_ms_median", median(decode_cpu_ms)}};
  }
  // The small streams, for the budget: one message each, record overhead included.
  const auto overhead = sealed_size(0);
  const double eye = double(encode_message(EyeMessage{1, {0, 0, -0.7}, true}).size() + overhead);
  HandSkeleton hand;
  for (auto& digit : hand.digits) digit.fill(Eigen::Vector3d::Zero());
  const double skeleton = double(encode_message(SkeletonMessage{1, {hand, hand}}).size() + overhead);
  const double heartbeat = double(encode_message(HeartbeatMessage{1, 1}).size() + overhead);
  std::printf("  small streams on the wire: eye %.0f B (30 Hz: %.1f kB/s), two-hand skeleton %.0f B (50 Hz: %.1f kB/s), "
              "heartbeat %.0f B (5 Hz)\n",
              eye, eye * 30 / 1e3, skeleton, skeleton * 50 / 1e3, heartbeat);
  report["record_overhead_bytes"] = overhead;
  report["eye_record_bytes"] = eye;
  report["skeleton_record_bytes"] = skeleton;
  report["heartbeat_record_bytes"] = heartbeat;
  report["sender_counters"] = sender.counters().to_json();
  std::filesystem::create_directories(options.out);
  std::ofstream(options.out / "bench_net.json") << report.dump(2) << "\n";
  return 0;
}

std::unique_ptr<Command> make_bench_net_command() {
  class BenchNet : public BenchCommand {
   public:
    BenchNet()
        : BenchCommand("net",
                       "Portraits at 30 fps from one session to another over loopback: bytes per portrait by part, "
                       "bytes per second on the wire, encode/decode ms; OUT/bench_net.json",
                       "Portraits per size", "640x360 and 1280x720") {}
    int run() override { return run_bench_net(options_); }
  };
  return std::make_unique<BenchNet>();
}

}  // namespace rt::app
