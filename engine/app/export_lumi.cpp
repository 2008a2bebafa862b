// The command line of export lumi; the work itself is pipeline/jobs/export_lumi.cpp.
#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/lumi_export.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class ExportLumiCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = parent.add_subcommand(
        "lumi", "Lumi-Net's training data: the network's inputs and the truth at its resolution, per frame (scripts/train-lumi)");
    command->add_option("--scene", export_.scene, "Scene name under assets/scenes/, or a scene file (not an evaluation scene)")
        ->capture_default_str();
    command->add_option("--site", export_.site, "Whose user is rendered")->check(CLI::IsMember({"A", "B"}))->capture_default_str();
    command->add_option("--scale", export_.scale, "The network's resolution: 1/scale of the target's")
        ->check(CLI::IsMember({1u, 2u, 4u}))
        ->capture_default_str();
    command->add_option("--supersample", export_.supersample, "Simulated color and truth at N x N samples per pixel (odd)")
        ->check(CLI::IsMember({1u, 3u, 5u, 7u}))
        ->capture_default_str();
    command->add_option("--first-frame", export_.first_frame, "Scene frame to start at")
        ->check(CLI::Range(0u, 1000000u))
        ->capture_default_str();
    command->add_option("--frame-step", export_.frame_step, "Every Nth scene frame")->check(CLI::Range(1u, 1000u))->capture_default_str();
    ibr_ = add_ibr_options(*command, {});
    add_run_options(*command, options_, "out/export-lumi");
    frames_ = add_frames_option(*command, options_, 1, "the rest of the scene from --first-frame at --frame-step");
    options_.width = 640;
    options_.height = 360;
    add_size_options(*command, options_, "Target view", 1, 16384);
    return command;
  }
  void check() override {
    export_.frames_given = frames_->count() > 0;
    ibr_.apply(export_.ibr);
  }
  int run() override { return run_export_lumi(options_, export_); }

 private:
  RunOptions options_;
  ExportLumiOptions export_;
  IbrOptions ibr_;
  CLI::Option* frames_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> make_export_lumi_command() { return std::make_unique<ExportLumiCommand>(); }

}  // namespace rt::app
