// `remotetouch list-cameras` and `remotetouch record --site SITE.json --out DIR --seconds S`:
// the connected k4a devices (Azure Kinect DK, Orbbec Femto) by serial number, and a site's live
// cameras written as k4a recordings that `site --replay`'s folders and `eval ibr --cameras-from`
// play (devices/camera/k4a_live_recorder.h). libk4a.so.1.4 is loaded only here, at run time.
#include <cstdio>

#include "app/command.h"
#include "camera/k4a_library.h"
#include "camera/k4a_live_camera.h"
#include "camera/k4a_live_recorder.h"
#include "sim/site_description.h"

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
    return command;
  }
  int run() override {
    const sim::SiteDescription site = sim::load_site(site_);
    const camera::k4a::RecordSummary summary =
        camera::k4a::record_live_site(site, "'" + site_.string() + "'", out_, seconds_);
    std::printf("record: %.1f s of %zu cameras into '%s' (captures:", summary.seconds, summary.captures.size(),
                out_.string().c_str());
    for (size_t count : summary.captures) std::printf(" %zu", count);
    std::printf("; %zu left out)\n", summary.skipped);
    return 0;
  }

 private:
  std::filesystem::path site_, out_;
  double seconds_ = 10.0;
};

}  // namespace

std::unique_ptr<Command> make_list_cameras_command() { return std::make_unique<ListCamerasCommand>(); }
std::unique_ptr<Command> make_record_command() { return std::make_unique<RecordCommand>(); }

}  // namespace rt::app
