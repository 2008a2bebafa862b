// `remotetouch inspect-camera FILE.mkv --out DIR`: what a k4a recording (Azure Kinect, Orbbec
// Femto) holds, as our reader sees it; the work is devices/camera/k4a_inspection.cpp.
#include <cstdio>

#include "app/command.h"
#include "camera/k4a_inspection.h"

namespace rt::app {
namespace {

class InspectCameraCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = parent.add_subcommand(
        "inspect-camera", "Read a k4a recording (Azure Kinect / Orbbec Femto .mkv): modes, intrinsics, first captures");
    command->add_option("file", file_, "The recording, one camera's .mkv")->required();
    command->add_option("--frames", frames_, "Captures to decode and write")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    command->add_option("--out", out_, "Folder for camera.json, color_NNNN.png and depth_NNNN.png (16-bit mm)")
        ->required();
    return command;
  }
  int run() override {
    const camera::k4a::InspectionSummary summary = camera::k4a::inspect_recording(file_, frames_, out_);
    std::printf("inspect-camera: %zu captures of '%s' -> %s (demuxed and decoded in %.1f ms a capture)\n",
                summary.captures, file_.string().c_str(), (out_ / "camera.json").string().c_str(),
                summary.decode_ms / double(summary.captures));
    return 0;
  }

 private:
  std::filesystem::path file_, out_;
  uint32_t frames_ = 1;
};

}  // namespace

std::unique_ptr<Command> make_inspect_camera_command() { return std::make_unique<InspectCameraCommand>(); }

}  // namespace rt::app
