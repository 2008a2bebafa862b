// `remotetouch inspect-camera FILE.mkv --out DIR`: what a k4a recording (Azure Kinect, Orbbec
// Femto) holds, as our reader sees it; the reading is devices/camera/k4a_inspection.cpp, the
// depth registered into colour is the GPU pass depth_in_color (pipeline/depth_registration.h).
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>

#include "app/command.h"
#include "camera/k4a_inspection.h"
#include "image/image_io.h"
#include "pipeline/depth_registration.h"
#include "pipeline/gpu_session.h"

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
    command
        ->add_option("--out", out_,
                     "Folder for camera.json, color_NNNN.png, depth_NNNN.png and depth_in_color_NNNN.png (16-bit mm), "
                     "points_NNNN.ply")
        ->required();
    command->add_option("--device", options_.device,
                        "Vulkan device for the depth registration: a part of its name (or REMOTETOUCH_DEVICE)");
    command->add_flag("--validation", options_.validation, "Enable the Khronos validation layer; errors fail the run");
    return command;
  }

  int run() override {
    options_.out = out_;
    // The GPU is started at the first capture with depth, so that a file we cannot read is
    // refused before, and without, a Vulkan device.
    std::optional<pipeline::GpuSession> session;
    std::unique_ptr<pipeline::DepthRegistration> registration;
    size_t registered = 0;
    auto register_depth = [&](size_t index, const camera::k4a::Capture& capture, const camera::k4a::RecordingInfo& info) {
      if (capture.depth_mm.width == 0) return;
      if (!registration) {
        session.emplace(options_);
        registration = std::make_unique<pipeline::DepthRegistration>(session->context(), info.depth, info.color,
                                                                     info.color_from_depth());
      }
      char name[64];
      std::snprintf(name, sizeof(name), "depth_in_color_%04zu.png", index);
      write_image(out_ / name, registration->run(capture.depth_mm), PngDepth::Sixteen);
      ++registered;
    };
    const camera::k4a::InspectionSummary summary = camera::k4a::inspect_recording(file_, frames_, out_, register_depth);
    std::printf("inspect-camera: %zu captures of '%s' -> %s (demuxed and decoded in %.1f ms a capture", summary.captures,
                file_.string().c_str(), (out_ / "camera.json").string().c_str(),
                summary.decode_ms / double(summary.captures));
    if (registration) {
      std::printf("; depth_in_color %.3f ms a capture (", registration->median_ms());
      const char* separator = "";
      for (const vk::PassTiming& timing : registration->timings())
        std::printf("%s%s %.3f", std::exchange(separator, ", "), timing.name.c_str(), timing.median_ms);
      std::printf(") on %s, %zu registered", session->context().device_name().c_str(), registered);
    }
    std::printf(")\n");
    return 0;
  }

 private:
  std::filesystem::path file_, out_;
  uint32_t frames_ = 1;
  pipeline::RunOptions options_;
};

}  // namespace

std::unique_ptr<Command> make_inspect_camera_command() { return std::make_unique<InspectCameraCommand>(); }

}  // namespace rt::app
