#include "camera/k4a_site_recordings.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <limits>
#include <thread>

#include "camera/each_camera_in_parallel.h"
#include "camera/k4a_site_writer.h"
#include "camera/site_camera_sources.h"

namespace rt::camera::k4a {

namespace {

// A day at 30 fps; the index holds a few numbers a capture, so a longer file is refused rather
// than indexed without bound.
constexpr size_t kMaxCapturesPerRecording = 3'000'000;
// Problems are reported one line each up to here, and counted beyond.
constexpr size_t kMaxReports = 5;

}  // namespace

struct SiteRecordings::Camera {
  std::filesystem::path file;
  std::unique_ptr<RecordingReader> reader;
  size_t next_in_file = 0;            // the reader's next capture, counted from the file's start
  std::vector<size_t> in_file;        // a kept capture's place in the file
  std::vector<uint64_t> aligned_us;   // a kept capture's time on the site's clock
};

bool is_site_of_recordings(const std::filesystem::path& dir) {
  std::error_code error;
  return std::filesystem::is_regular_file(dir / "site.json", error) &&
         !std::filesystem::exists(dir / "calibration.json", error);
}

void SiteRecordings::report(const std::string& problem) {
  if (!log_) return;
  if (reported_ < kMaxReports) std::fprintf(log_, "k4a replay: %s\n", problem.c_str());
  if (reported_ == kMaxReports) std::fprintf(log_, "k4a replay: further problems are only counted\n");
  ++reported_;
}

void SiteRecordings::open_reader(Camera& camera) {
  camera.reader = std::make_unique<RecordingReader>(camera.file);
  camera.next_in_file = 0;
}

SiteRecordings::SiteRecordings(const std::filesystem::path& dir, std::FILE* log, size_t max_cameras)
    : dir_(dir), log_(log), decode_threads_(std::max(1u, std::thread::hardware_concurrency())) {
  site_ = sim::load_site(dir_ / "site.json");
  if (site_.cameras.empty()) throw RecordingError("'" + (dir_ / "site.json").string() + "' lists no cameras");
  if (max_cameras > 0 && site_.cameras.size() > max_cameras) site_.cameras.resize(max_cameras);

  const std::string site_file = "'" + (dir_ / "site.json").string() + "'";
  std::vector<CameraSource> sources;
  try {
    sources = camera_sources(site_, dir_, site_file);
  } catch (const std::runtime_error& error) {
    throw RecordingError(error.what());
  }
  std::vector<int64_t> first_device_us;
  for (size_t index = 0; index < site_.cameras.size(); ++index) {
    sim::RgbdCamera& described = site_.cameras[index];
    if (sources[index].kind == CameraSourceKind::k4a_live)
      throw RecordingError(site_file + ": camera '" + described.name +
                           "' is a live device (source \"k4a\"), and this site plays recordings: give it "
                           "\"k4a-recording:PATH\", or play the live site with `remotetouch record`");
    auto camera = std::make_unique<Camera>();
    // A camera that names no recording plays the one beside site.json under its own name.
    camera->file = sources[index].kind == CameraSourceKind::k4a_recording ? sources[index].recording
                                                                           : recording_path(dir_, described.name);
    if (!std::filesystem::is_regular_file(camera->file))
      throw RecordingError("'" + dir_.string() + "': camera '" + described.name + "' of site.json has no recording '" +
                           camera->file.string() + "'");
    open_reader(*camera);
    const RecordingInfo& info = camera->reader->info();
    const std::string where = "'" + camera->file.string() + "'";
    if (!infos_.empty() && info.fps != infos_.front().fps)
      throw RecordingError(where + " records at " + std::to_string(info.fps) + " fps, '" +
                           cameras_.front()->file.string() + "' at " + std::to_string(infos_.front().fps) +
                           ": a site's cameras record at one rate");
    // The depth camera may expose later than the colour camera: a moving hand is then in two
    // places in the two images, which the registration cannot undo.
    if (info.depth_delay_ns != 0 && log_)
      std::fprintf(log_, "k4a replay: %s: depth is taken %lld us %s colour (K4A_DEPTH_DELAY_NS)\n", where.c_str(),
                   static_cast<long long>(std::llabs(info.depth_delay_ns) / 1000), info.depth_delay_ns > 0 ? "after" : "before");
    CameraIntrinsics color_lens;
    try {
      color_lens = color_lens_for(described, info.color, site_file);
    } catch (const std::runtime_error& error) {
      throw RecordingError(error.what());
    }
    described.color = color_lens;
    described.depth = info.depth;
    recorded_.push_back({color_lens, info.depth, info.color_from_depth()});
    infos_.push_back(info);
    cameras_.push_back(std::move(camera));
  }

  // Index every capture by its times, images left undecoded.
  std::vector<std::vector<uint64_t>> device_us(cameras_.size());
  for (size_t k = 0; k < cameras_.size(); ++k) {
    Camera& camera = *cameras_[k];
    const RecordingInfo& info = infos_[k];
    const std::string where = "'" + camera.file.string() + "'";
    const uint64_t subordinate_delay_us = info.wired_sync == WiredSyncMode::subordinate ? info.subordinate_delay_ns / 1000 : 0;
    for (size_t index = 0;; ++index) {
      std::optional<CaptureTimes> times;
      try {
        times = camera.reader->skip_capture();
      } catch (const RecordingError& error) {
        report(std::string(error.what()) + ": played up to there");
        break;
      }
      if (!times) break;
      if (!times->color_device_us || !times->depth_device_us) {
        ++skipped_;
        report(where + ": the capture at device time " +
               std::to_string(times->color_device_us.value_or(times->depth_device_us.value_or(0))) + " us has no " +
               (times->color_device_us ? "depth" : "colour") + " image: its camera sits out that frame set");
        continue;
      }
      const uint64_t aligned = *times->color_device_us - std::min(*times->color_device_us, subordinate_delay_us);
      if (!device_us[k].empty() && aligned <= device_us[k].back()) {
        ++skipped_;
        report(where + ": the capture at device time " + std::to_string(*times->color_device_us) +
               " us is not after the one before it: left out");
        continue;
      }
      if (device_us[k].size() >= kMaxCapturesPerRecording)
        throw RecordingError(where + " has more than " + std::to_string(kMaxCapturesPerRecording) +
                             " captures; split it into shorter recordings");
      device_us[k].push_back(aligned);
      camera.in_file.push_back(index);
    }
    if (device_us[k].empty())
      throw RecordingError(where + " has no capture with both a colour and a depth image");
    first_device_us.push_back(int64_t(device_us[k].front()));
  }

  // Cameras in wired sync share the master's clock. Standalone devices each count from their own
  // start, so when their clocks are apart they are put together by the time since each file
  // started, which is as good as the recordings were started together.
  const uint64_t period_us = frame_period_ns(infos_.front().fps) / 1000;
  const auto [lowest, highest] = std::minmax_element(first_device_us.begin(), first_device_us.end());
  const bool all_standalone = std::all_of(infos_.begin(), infos_.end(), [](const RecordingInfo& info) {
    return info.wired_sync == WiredSyncMode::standalone;
  });
  clock_ = "device time";
  if (all_standalone && uint64_t(*highest - *lowest) >= period_us / 2) {
    clock_ = "time since each recording's start (standalone cameras whose device clocks are " +
             std::to_string((*highest - *lowest) / 1000) + " ms apart)";
    uint64_t earliest_start = std::numeric_limits<uint64_t>::max();
    for (const RecordingInfo& info : infos_) earliest_start = std::min(earliest_start, info.start_offset_us);
    for (size_t k = 0; k < cameras_.size(); ++k)
      for (uint64_t& time : device_us[k]) time = time - std::min(time, infos_[k].start_offset_us) + earliest_start;
  }
  sets_ = assemble_frame_sets(device_us, period_us);
  for (size_t k = 0; k < cameras_.size(); ++k) {
    cameras_[k]->aligned_us = std::move(device_us[k]);
    open_reader(*cameras_[k]);  // the index read each file to its end
  }
}

SiteRecordings::~SiteRecordings() = default;

void SiteRecordings::seek(size_t i) {
  if (i > sets_.size())
    throw std::out_of_range("k4a recordings in '" + dir_.string() + "' have " + std::to_string(sets_.size()) +
                            " frame sets, cannot seek to " + std::to_string(i));
  next_ = i;
}

const DecodeTimes& SiteRecordings::decode_times(size_t k) const { return cameras_.at(k)->reader->decode_times(); }

sim::RgbdImage SiteRecordings::read_camera(size_t k, const FrameSet& set, std::string& problem) {
  Camera& camera = *cameras_[k];
  sim::RgbdImage image;
  image.camera = site_.cameras[k].name;
  image.timestamp_us = set.time_us;
  const std::optional<size_t> kept = set.captures[k];
  if (!kept) return image;
  const size_t in_file = camera.in_file[*kept];
  try {
    if (camera.next_in_file > in_file) open_reader(camera);  // backwards: from the start again
    for (; camera.next_in_file < in_file; ++camera.next_in_file) camera.reader->skip_capture();
    ++camera.next_in_file;
    if (std::optional<Capture> capture = camera.reader->next_capture()) {
      image.color = std::move(capture->color);
      image.depth_mm = std::move(capture->depth_mm);
      image.timestamp_us = camera.aligned_us[*kept];
    }
  } catch (const RecordingError& error) {
    problem = std::string(error.what()) + ": its camera sits out frame set " + std::to_string(next_);
  }
  return image;
}

std::optional<sim::RgbdFrame> SiteRecordings::next_frame() {
  if (next_ >= sets_.size()) return std::nullopt;
  const FrameSet& set = sets_[next_];
  sim::RgbdFrame frame;
  frame.index = next_;
  frame.timestamp_us = set.time_us;
  const size_t count = cameras_.size();
  frame.cameras.resize(count);
  std::vector<std::string> problems(count);
  for_each_camera_in_parallel(count, decode_threads_,
                              [&](size_t k) { frame.cameras[k] = read_camera(k, set, problems[k]); });
  for (size_t k = 0; k < count; ++k) {
    if (!problems[k].empty()) {
      ++skipped_;
      report(problems[k]);
    }
    // A camera without this set's capture contributes no surface: the others render the user.
    sim::RgbdImage& image = frame.cameras[k];
    if (image.color.texels.empty() || image.depth_mm.texels.empty()) {
      image.color = HostImage(recorded_[k].color.width, recorded_[k].color.height, PixelFormat::RGBA8);
      image.depth_mm = HostImage(recorded_[k].depth.width, recorded_[k].depth.height, PixelFormat::R16U);
    }
  }
  ++next_;
  return frame;
}

}  // namespace rt::camera::k4a
