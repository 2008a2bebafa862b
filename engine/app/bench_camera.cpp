// `remotetouch bench camera DIR`: how fast a site's k4a recordings are demuxed and decoded into
// frame sets (camera/k4a_site_recordings.h), stage by stage, on one thread and on every core.
// The images stay in host memory: what the GPU upload then costs is bench ibr's to report.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/bench_command.h"
#include "camera/k4a_site_recordings.h"

namespace rt::app {
namespace {

class BenchCamera : public BenchCommand {
 public:
  BenchCamera()
      : BenchCommand("camera",
                     "A site's k4a recordings demuxed and decoded into frame sets: ms per camera by stage, frame "
                     "sets a second on one thread and on every core",
                     "Frame sets to decode (fewer when the recordings hold fewer)") {}

  int run() override {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    nlohmann::json report = {{"recordings", dir_.string()}, {"cores", cores}};
    std::printf("bench camera: '%s', %u cores\n", dir_.string().c_str(), cores);
    std::printf("%-8s %8s %9s %12s %11s %12s %11s %13s %10s\n", "threads", "cameras", "sets", "demux ms", "jpeg ms",
                "convert ms", "to-host ms", "ms per set", "sets/s");
    for (const unsigned threads : {1u, cores}) {
      camera::k4a::SiteRecordings site(dir_, stderr, cameras_);
      site.set_decode_threads(threads);
      const size_t sets = std::min<size_t>(options_.frames, site.frame_count());
      const auto start = std::chrono::steady_clock::now();
      for (size_t i = 0; i < sets; ++i) site.next_frame();
      const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      camera::k4a::DecodeTimes sum;
      const size_t cameras = site.site().cameras.size();
      for (size_t k = 0; k < cameras; ++k) {
        const camera::k4a::DecodeTimes& times = site.decode_times(k);
        sum.captures += times.captures;
        sum.demux_ms += times.demux_ms;
        sum.color_decode_ms += times.color_decode_ms;
        sum.color_convert_ms += times.color_convert_ms;
        sum.to_host_ms += times.to_host_ms;
      }
      const double per = sum.captures ? 1.0 / double(sum.captures) : 0.0;
      const double per_set_ms = sets ? wall_ms / double(sets) : 0.0;
      std::printf("%-8u %8zu %9zu %12.2f %11.2f %12.2f %11.2f %13.2f %10.1f\n", threads, cameras, sets,
                  sum.demux_ms * per, sum.color_decode_ms * per, sum.color_convert_ms * per, sum.to_host_ms * per,
                  per_set_ms, per_set_ms > 0 ? 1000.0 / per_set_ms : 0.0);
      report["runs"].push_back({{"threads", threads},
                                {"cameras", cameras},
                                {"sets", sets},
                                {"captures", sum.captures},
                                {"ms_per_capture", {{"demux", sum.demux_ms * per},
                                                    {"color_decode", sum.color_decode_ms * per},
                                                    {"color_convert", sum.color_convert_ms * per},
                                                    {"to_host", sum.to_host_ms * per}}},
                                {"ms_per_set", per_set_ms},
                                {"sets_per_s", per_set_ms > 0 ? 1000.0 / per_set_ms : 0.0}});
    }
    std::printf("stage times are per camera's capture, summed over threads; ms per set is wall time\n");
    std::filesystem::create_directories(options_.out);
    std::ofstream(options_.out / "bench_camera.json") << report.dump(2) << "\n";
    std::printf("written to %s\n", (options_.out / "bench_camera.json").string().c_str());
    return 0;
  }

 protected:
  void add_options(CLI::App& command) override {
    command.add_option("recordings", dir_, "A site's k4a recordings: site.json and one .mkv per camera")
        ->required()
        ->check(CLI::ExistingDirectory);
    command.add_option("--cameras", cameras_, "Only the first N cameras of site.json (0: all)")
        ->check(CLI::Range(0u, 64u))
        ->capture_default_str();
  }

 private:
  std::filesystem::path dir_;
  size_t cameras_ = 0;
};

}  // namespace

std::unique_ptr<Command> make_bench_camera_command() { return std::make_unique<BenchCamera>(); }

}  // namespace rt::app
