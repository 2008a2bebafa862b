// The command line of simulate; the work itself is pipeline/jobs/simulate.cpp.

#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class SimulateCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    command_ = parent.add_subcommand("simulate", "Record one site of a synthetic scene: RGBD cameras, tracker, ground truth");
    command_->add_option("--scene", simulate_.scene, "Scene name under assets/scenes/, or a scene file")->capture_default_str();
    command_->add_option("--site", site_, "Which site to record")->check(CLI::IsMember({"A", "B"}))->capture_default_str();
    add_run_options(*command_, options_, "out/simulate");
    frames_ = add_frames_option(*command_, options_, 1, "the scene's own count");
    frames_->description("Frames to record");
    add_inspection_options(*command_, options_);
    command_->add_option("--resolution-scale", simulate_.resolution_scale, "Camera resolution scale")
        ->check(CLI::Range(0.01, 1.0))
        ->default_str("the scene's");
    command_->add_option("--format", simulate_.format,
                         "recording: PNG folders (README); k4a: one Azure Kinect recording (.mkv, MJPG colour, "
                         "b16g depth, calibration.json) per camera, site.json beside them. k4a needs every camera's "
                         "images at a k4a mode's size (colour 1280x720 .. 4096x3072, depth 320x288 .. 1024x1024; "
                         "the default site at --resolution-scale 1): other sizes are refused, not resampled")
        ->check(CLI::IsMember({"recording", "k4a"}))
        ->capture_default_str();
    command_->add_option("--jpeg-quality", simulate_.jpeg_quality, "k4a colour: the MJPG quality")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    command_->add_option("--supersample", simulate_.supersample,
                         "Camera colour and ground truth rendered at N x N samples per pixel, box-filtered (odd; "
                         "eval ibr renders at 3)")
        ->check(CLI::IsMember({1u, 3u, 5u, 7u}))
        ->default_str("the scene's");
    command_->add_option("--gt-width", simulate_.gt_width, "Ground-truth target view width")
        ->check(CLI::Range(1u, 16384u))->capture_default_str();
    command_->add_option("--gt-height", simulate_.gt_height, "Ground-truth target view height")
        ->check(CLI::Range(1u, 16384u))->capture_default_str();
    return command_;
  }
  void check() override {
    simulate_.frames_given = frames_->count() > 0;
    simulate_.site = site_ == "B" ? Site::B : Site::A;
    if (simulate_.frames_given) check_capture_frame(options_);
  }
  int run() override { return run_simulate(options_, simulate_); }

 private:
  CLI::App* command_ = nullptr;
  CLI::Option* frames_ = nullptr;
  RunOptions options_;
  SimulateOptions simulate_;
  std::string site_ = "A";
};

}  // namespace

std::unique_ptr<Command> make_simulate_command() { return std::make_unique<SimulateCommand>(); }


}  // namespace rt::app
