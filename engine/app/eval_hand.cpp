// The command line of eval hand; the work itself is pipeline/jobs/eval_hand.cpp.
#include <cmath>

#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class EvalHandCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = parent.add_subcommand("hand", "Measure the geometry hand: skinning, shape and appearance adaption");
    add_run_options(*command, options_, "out/eval-hand");
    options_.width = 960;
    options_.height = 540;
    add_size_options(*command, options_, "Target view", 16, 16384);
    return command;
  }
  int run() override { return run_eval_hand(options_); }

 private:
  RunOptions options_;
};

}  // namespace

std::unique_ptr<Command> make_eval_hand_command() { return std::make_unique<EvalHandCommand>(); }

}  // namespace rt::app
