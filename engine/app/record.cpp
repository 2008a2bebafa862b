// `remotetouch list-cameras` and `remotetouch record --site SITE.json --out DIR --seconds S`:
// the connected k4a devices (Azure Kinect DK, Orbbec Femto) by serial number, and a site's live
// cameras written as k4a recordings that `site --replay`'s folders and `eval ibr --cameras-from`
// play (devices/camera/k4a_live_recorder.h). libk4a.so.1.4 is loaded only here, at run time.
#include <chrono>
#include <cstdio>
#include <optional>

#include "app/command.h"
#include "camera/k4a_library.h"
#include "camera/k4a_live_camera.h"
#include "camera/k4a_live_recorder.h"
#include "sim/site_description.h"
#include "site/site_options.h"
#include "tracker/leap_recorder.h"
#include "tracker/leap_service.h"

namespace rt::app {
namespace {

class ListCamerasCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    return parent.add_subcommand("list-cameras",
                                 "List the connected Azure Kinect / Orbbec Femto devices by serial (needs libk4a.so.1.4)");
  }
  int run() override {
    const auto library = camera::k4a::load_k4a_library();
    size_t unopened = 0;
    const std::vector<std::string> serials = camera::k4a::connected_serials(*library, &unopened);
    std::printf("list-cameras: %zu k4a device(s) through '%s'\n", serials.size() + unopened, library->path.c_str());
    for (const std::string& serial : serials) std::printf("  serial %s\n", serial.empty() ? "(none)" : serial.c_str());
    if (unopened > 0)
      std::printf("  %zu more could not be opened (another program, such as k4aviewer, may hold them)\n", unopened);
    if (serials.empty() && unopened == 0)
      std::printf("  none: plug the device in by USB 3 and power it; `lsusb` should list it\n");
    return 0;
  }
};

class RecordCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = parent.add_subcommand(
        "record", "Record a site's live k4a cameras (Azure Kinect / Orbbec Femto) as one .mkv per camera");
    command->add_option("--site", site_, "The site file; every camera's source \"k4a\" with its serial")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("--out", out_, "A new folder: site.json and <camera name>.mkv, a site of recordings")->required();
    command->add_option("--seconds", seconds_, "How long to record")->check(CLI::Range(0.1, 86400.0))->capture_default_str();
    command->add_option("--tracker", tracker_,
                        "Also record the hands: leap (the Leap service at its default address) or "
                        "leap:ws://HOST:PORT/PATH, written as tracker.jsonl on the cameras' clock, so that the "
                        "folder replays with its hands; none records the cameras only")
        ->capture_default_str();
    return command;
  }
  int run() override {
    const sim::SiteDescription site = sim::load_site(site_);
    std::optional<std::string> leap_url;
    if (tracker_ != "none") {
      leap_url = site::leap_tracker_url(tracker_);
      if (!leap_url) throw std::invalid_argument("record --tracker: '" + tracker_ + "' is not leap, leap:URL or none");
    }
    // The service is reached before the cameras start, so that a missing one costs no recording.
    std::unique_ptr<devices::LeapServiceTracker> leap;
    std::unique_ptr<devices::LeapRecorder> leap_recorder;
    if (leap_url) {
      devices::LeapServiceTracker::Options leap_options;
      leap_options.url = *leap_url;
      leap = std::make_unique<devices::LeapServiceTracker>(leap_options);
      leap->wait_connected(std::chrono::seconds(3));
      std::filesystem::create_directories(out_);
      leap_recorder = std::make_unique<devices::LeapRecorder>(*leap, out_ / "tracker.arrivals.jsonl");
    }
    camera::k4a::RecordSummary summary;
    try {
      summary = camera::k4a::record_live_site(site, "'" + site_.string() + "'", out_, seconds_);
    } catch (...) {
      leap_recorder.reset();
      std::error_code ignored;
      std::filesystem::remove(out_ / "tracker.arrivals.jsonl", ignored);
      throw;
    }
    std::printf("record: %.1f s of %zu cameras into '%s' (captures:", summary.seconds, summary.captures.size(),
                out_.string().c_str());
    for (size_t count : summary.captures) std::printf(" %zu", count);
    std::printf("; %zu left out)\n", summary.skipped);
    if (leap_recorder) {
      const devices::LeapRecording hands = leap_recorder->finish(out_ / "tracker.jsonl", summary.host_minus_device_us);
      std::printf("record: %llu tracker frames (%llu with hands, %llu replaced before they were read) from %s into "
                  "tracker.jsonl\n",
                  static_cast<unsigned long long>(hands.frames), static_cast<unsigned long long>(hands.frames_with_hands),
                  static_cast<unsigned long long>(hands.frames_missed), leap->url().text().c_str());
    }
    return 0;
  }

 private:
  std::filesystem::path site_, out_;
  double seconds_ = 10.0;
  std::string tracker_ = "none";
};

}  // namespace

std::unique_ptr<Command> make_list_cameras_command() { return std::make_unique<ListCamerasCommand>(); }
std::unique_ptr<Command> make_record_command() { return std::make_unique<RecordCommand>(); }

}  // namespace rt::app
