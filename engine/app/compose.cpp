// The command line of compose; the work itself is pipeline/jobs/compose.cpp.

#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class ComposeCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command =
        parent.add_subcommand("compose", "The compositing passes alone on generated layers (pass dumps, RenderDoc captures)");
    add_run_options(*command, options_, "out/compose");
    add_frames_option(*command, options_, 30);
    add_inspection_options(*command, options_);
    options_.width = 640;
    options_.height = 360;
    add_size_options(*command, options_, "Frame", 1, 16384);
    command->add_flag("--dump-passes", options_.dump_passes, "Write every pass output of the last frame (EXR and PNG) to OUT/passes/");
    return command;
  }
  void check() override { check_capture_frame(options_); }
  int run() override { return run_compose(options_); }

 private:
  RunOptions options_;
};

}  // namespace

std::unique_ptr<Command> make_compose_command() { return std::make_unique<ComposeCommand>(); }

}  // namespace rt::app
